//! Writes `sceneeval relate` query files (JSON lines) to standard output, for measuring the
//! command (see the `relate` section of `docs/performance.md`). Deterministic: the same
//! arguments always give the same bytes (a fixed-seed generator, no dependencies).
//!
//! ```text
//! relate-queries pairs N                      N box-box queries: the 12 two-object relations
//!                                             in turn on random box pairs
//! relate-queries arch N [inline|declared|all-declared] [R]
//!                                             N object-architecture queries on the bed 5 cm
//!                                             from the head wall of the benchmark bedroom
//!                                             (`benches/benches/relations.rs`), the 10
//!                                             relations in turn or only R; the room written
//!                                             in every query (default) or declared once, or
//!                                             the room and the bed declared once
//! relate-queries suite                        6,900 queries: 300 for each of the 23 relations
//!                                             on random boxes, rooms written in every query
//! ```

#![allow(clippy::print_stdout, clippy::print_stderr)]

use std::fmt::Write as _;
use std::io::{self, BufWriter, Write};
use std::process::ExitCode;

use sceneeval_test_support::Lcg;

/// The benchmark bedroom: 4 x 5 m, a door on wall 0, a window on wall 1 (x = 4).
const ROOM: &str = r#"{"floor":[[0,0],[4,0],[4,5],[0,5]],"height":2.8,"wall_thickness":0.1,"openings":[{"kind":"door","wall":0,"along":[1.0,1.9],"height":[0.0,2.1]},{"kind":"window","wall":1,"along":[1.5,3.5],"height":[0.9,2.0]}]}"#;

/// The bed of the architecture benchmark: 5 cm from the head wall (y = 5), yaw 0.05.
const BED: &str = r#"{"center":[2.0,3.93,0.3],"half_size":[0.8,1.0,0.3],"yaw":0.05}"#;

/// The two-object relations, with their argument.
const PAIRS: [&str; 12] = [
    r#""relation":"inside_of""#,
    r#""relation":"outside_of""#,
    r#""relation":"face_to""#,
    r#""relation":"side_of","side":"left""#,
    r#""relation":"side_region","side":"front""#,
    r#""relation":"long_short_side_of","side":"long""#,
    r#""relation":"on_top""#,
    r#""relation":"middle_of""#,
    r#""relation":"next_to""#,
    r#""relation":"near""#,
    r#""relation":"across_from""#,
    r#""relation":"far""#,
];

/// The object-architecture relations, with their argument.
const ARCH: [&str; 10] = [
    r#""relation":"next_to","arch":"wall""#,
    r#""relation":"near","arch":"door""#,
    r#""relation":"across_from","arch":"window""#,
    r#""relation":"far","arch":"wall""#,
    r#""relation":"inside_room""#,
    r#""relation":"middle_of_room""#,
    r#""relation":"corner_of_room""#,
    r#""relation":"on_wall""#,
    r#""relation":"against_wall""#,
    r#""relation":"hang_from_ceiling""#,
];

/// Random boxes from the repository's fixed-seed generator.
struct Rng(Lcg);

impl Rng {
    /// Uniform in `[lo, hi)`, rounded to millimetres (short lines, like a client's).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let u = self.0.next();
        ((lo + u * (hi - lo)) * 1000.0).round() / 1000.0
    }

    /// A random box in a 4 x 5 m room, 0.1 to 1 m wide and deep, 0.1 to 1 m tall, on the
    /// floor or up to 1 m above it.
    fn a_box(&mut self) -> String {
        let h = [
            self.range(0.05, 0.5),
            self.range(0.05, 0.5),
            self.range(0.05, 0.5),
        ];
        let c = [
            self.range(0.3, 3.7),
            self.range(0.3, 4.7),
            h[2] + if self.0.next() < 0.5 {
                0.0
            } else {
                self.range(0.0, 1.0)
            },
        ];
        let yaw = self.range(-std::f64::consts::PI, std::f64::consts::PI);
        format!(
            r#"{{"center":[{},{},{}],"half_size":[{},{},{}],"yaw":{yaw}}}"#,
            c[0], c[1], c[2], h[0], h[1], h[2]
        )
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| args.get(i).map(String::as_str);
    let count = |i: usize| arg(i).and_then(|s| s.parse::<usize>().ok());
    let mut rng = Rng(Lcg(0x5CE4_E7A1));
    let mut text = String::new();
    match (arg(0), count(1)) {
        (Some("pairs"), Some(n)) => {
            for i in 0..n {
                let (t, a) = (rng.a_box(), rng.a_box());
                let r = PAIRS[i % PAIRS.len()];
                let _ = writeln!(text, r#"{{"id":{i},{r},"target":{t},"anchor":{a}}}"#);
            }
        }
        (Some("arch"), Some(n)) => {
            let (declared, bed_declared) = match arg(2) {
                None | Some("inline") => (false, false),
                Some("declared") => (true, false),
                Some("all-declared") => (true, true),
                Some(other) => {
                    return usage(&format!(
                        "expected inline, declared or all-declared, got {other:?}"
                    ));
                }
            };
            let only = arg(3);
            let relations: Vec<&str> = ARCH
                .iter()
                .copied()
                .filter(|r| only.is_none_or(|name| r.contains(&format!("\"{name}\""))))
                .collect();
            if relations.is_empty() {
                return usage(&format!("no architecture relation named {only:?}"));
            }
            let room = if declared {
                let _ = writeln!(text, r#"{{"declare":"bedroom","room":{ROOM}}}"#);
                "\"bedroom\"".to_owned()
            } else {
                ROOM.to_owned()
            };
            let bed = if bed_declared {
                let _ = writeln!(text, r#"{{"declare":"bed","object":{BED}}}"#);
                "\"bed\""
            } else {
                BED
            };
            for i in 0..n {
                let r = relations[i % relations.len()];
                let _ = writeln!(text, r#"{{"id":{i},{r},"target":{bed},"room":{room}}}"#);
            }
        }
        (Some("suite"), _) => {
            let mut i = 0;
            for _ in 0..300 {
                for r in PAIRS {
                    let (t, a) = (rng.a_box(), rng.a_box());
                    let _ = writeln!(text, r#"{{"id":{i},{r},"target":{t},"anchor":{a}}}"#);
                    i += 1;
                }
                let targets: Vec<String> = (0..4).map(|_| rng.a_box()).collect();
                let _ = writeln!(
                    text,
                    r#"{{"id":{i},"relation":"surround","anchor":{},"targets":[{}]}}"#,
                    rng.a_box(),
                    targets.join(",")
                );
                i += 1;
                for r in ARCH {
                    let _ = writeln!(text, r#"{{"id":{i},{r},"target":{},"room":{ROOM}}}"#, rng.a_box());
                    i += 1;
                }
            }
        }
        _ => {
            return usage(
                "expected `pairs N`, `arch N [inline|declared|all-declared] [RELATION]` or `suite`",
            );
        }
    }
    let mut out = BufWriter::new(io::stdout().lock());
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("relate-queries: {e}");
            ExitCode::FAILURE
        }
    }
}

fn usage(problem: &str) -> ExitCode {
    eprintln!("relate-queries: {problem}");
    ExitCode::from(2)
}
