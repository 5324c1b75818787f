//! Shared set-up for the benchmarks under `benches/benches/`.

pub mod scenes;
