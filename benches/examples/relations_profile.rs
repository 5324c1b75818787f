//! Runs one predicate of the relation benchmarks (`benches/relations.rs`, same
//! configurations), its score alone or with its gradient, a given number of times, for
//! instruction counts that do not depend on the machine's load:
//!
//! ```text
//! cargo build --profile bench -p sceneeval-benches --example relations-profile
//! valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
//!     target/release/examples/relations-profile box grad on_top 10000
//! ```
//!
//! Arguments: the configuration (`box`, `mesh`, `room_box`, `room_mesh`), `score` or `grad`,
//! the predicate's benchmark name (`inside_of`, ..., and with `box` also `surround_4`,
//! `face_to_tv` and `face_to_mesh_tv`), and the number of calls. The difference between the
//! counts of `N` and `0` calls, over `N`, is one call's (docs/performance.md, Gradients).

// A measuring tool: it stops on a set-up failure or a bad argument.
#![allow(clippy::expect_used, clippy::panic)]

#[path = "../benches/relations_configs/mod.rs"]
mod configs;

use std::hint::black_box;

use configs::{
    arch_relations, bed_and_stand, bx, mesh_bed_and_stand, pair_relations, room, sofa_and_tv, wall_bed,
};
use sceneeval_geom::Real;
use sceneeval_relations::grad::BoxGrad;
use sceneeval_relations::{ObjectGeom, RelationParams, arch, batch, grad, surround};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [config, kind, name, calls] = args.as_slice() else {
        panic!("usage: relations-profile box|mesh|room_box|room_mesh score|grad NAME CALLS");
    };
    let calls: usize = calls.parse().expect("CALLS is a number");
    let with_grad = match kind.as_str() {
        "score" => false,
        "grad" => true,
        other => panic!("{other}: score or grad"),
    };
    let p = RelationParams::default();
    let (bed, stand) = bed_and_stand();
    let (mesh_bed, mesh_stand) = mesh_bed_and_stand();
    let (wall_box, wall_mesh) = wall_bed();
    let rooms = [room()];
    let table = bx([2.0, 2.5, 0.375], [0.6, 0.6, 0.375], 0.0);
    let chairs: Vec<_> = (0..4)
        .map(|k| {
            let ang = Real::from(k) * std::f64::consts::FRAC_PI_2 + 0.1;
            bx([2.0 + ang.cos(), 2.5 + ang.sin(), 0.45], [0.25, 0.25, 0.45], ang)
        })
        .collect();
    let around: Vec<ObjectGeom<'_>> = chairs.iter().map(ObjectGeom::from_box).collect();
    let mut d = [BoxGrad::ZERO; 4];
    let (sofa, tv, mesh_tv) = sofa_and_tv();
    let mut call: Box<dyn FnMut() -> Real> = match config.as_str() {
        "box" if name.starts_with("face_to_") => {
            let s = ObjectGeom::from_box(&sofa);
            let t = match name.as_str() {
                "face_to_tv" => ObjectGeom::from_box(&tv),
                "face_to_mesh_tv" => mesh_tv.view(),
                other => panic!("{other}: face_to_tv or face_to_mesh_tv"),
            };
            if with_grad {
                Box::new(move || grad::face_to(&s, &t, &p).score)
            } else {
                Box::new(move || sceneeval_relations::face_to(&s, &t, &p))
            }
        }
        "box" if name == "surround_4" => {
            let anchor = ObjectGeom::from_box(&table);
            if with_grad {
                Box::new(move || {
                    grad::surround(&around, &anchor, &p, &mut d)
                        .expect("four targets")
                        .0
                })
            } else {
                Box::new(move || surround(&around, &anchor, &p))
            }
        }
        "box" | "mesh" => {
            let r = pair_relations()
                .into_iter()
                .find(|(n, _)| n == name)
                .map(|(_, r)| r)
                .expect("a two-object relation of the benchmark");
            let (a, b) = if config == "box" {
                (ObjectGeom::from_box(&stand), ObjectGeom::from_box(&bed))
            } else {
                (mesh_stand.view(), mesh_bed.view())
            };
            if with_grad {
                Box::new(move || grad::pair(r, &a, &b, &p).expect("a pair relation").score)
            } else {
                Box::new(move || batch::score_pair(r, &a, &b, &p).expect("a pair relation"))
            }
        }
        "room_box" | "room_mesh" => {
            let r = arch_relations()
                .into_iter()
                .find(|(n, _)| n == name)
                .map(|(_, r)| r)
                .expect("an object-architecture relation of the benchmark");
            let a = if config == "room_box" {
                ObjectGeom::from_box(&wall_box)
            } else {
                wall_mesh.view()
            };
            let rooms = &rooms;
            if with_grad {
                Box::new(move || {
                    grad::arch_rooms(r, &a, rooms, &p)
                        .expect("an arch relation")
                        .score
                })
            } else {
                Box::new(move || arch::score_rooms(r, &a, rooms, &p).expect("an arch relation"))
            }
        }
        other => panic!("{other}: box, mesh, room_box or room_mesh"),
    };
    let mut total = 0.0;
    for _ in 0..calls {
        total += black_box(call());
    }
    black_box(total);
}
