//! Shared set-up for the benchmarks under `benches/benches/`.
