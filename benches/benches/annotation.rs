//! Criterion benchmarks of annotation files (`sceneeval-annotation`).
//!
//! A generated 500-row CSV the size of SceneEval-500 (each row: a 60-word description with a
//! comma, 8 ObjCount, 6 ObjAttr, 6 OORel incl. a `surround`, 3 OARel entries, two extra
//! columns; every tenth row with one malformed entry) is parsed, validated, written, and
//! summarised. Run with
//! `cargo bench -p sceneeval-benches --bench annotation -- --warm-up-time 1 --measurement-time 3`.

// A benchmark binary may stop on a set-up failure.
#![allow(clippy::expect_used)]

use std::fmt::Write as _;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use sceneeval_annotation::Annotations;

/// The benchmark file: deterministic, 500 rows.
fn csv_500() -> String {
    let mut s = String::from("ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel,Category,SceneEvalID\n");
    let description = ["A cosy room with a bed, two nightstands and a desk by the window"; 6].join(" and ");
    for i in 0..500 {
        let difficulty = ["easy", "medium", "hard"][i % 3];
        let malformed = if i % 10 == 0 { "; eq,x,lamp" } else { "" };
        let _ = writeln!(
            s,
            "{i},{difficulty},\"{description}.\",\
             \"eq,1,bed; eq,2,nightstand; eq,1,desk; eq,1,chair; eq,4,dining_chair; eq,1,table; ge,2,book; eq,1,rug{malformed}\",\
             \"eq,1,bed,king_size; eq,2,nightstand,white; eq,1,desk,wooden; eq,1,chair,red; eq,1,table,round; eq,1,rug,plush\",\
             \"eq,1,left,0,bed,nightstand; eq,1,right,0,bed,nightstand; eq,1,front,0,desk,chair; \
             eq,1,surround,0,table,dining_chair:0,dining_chair:1,dining_chair:2,dining_chair:3; ge,2,on,0,desk,book; eq,1,under,0,bed,rug\",\
             \"eq,1,against,bed,wall; eq,1,next_to,desk,window; eq,1,corner,table,room\",bench,{i}"
        );
    }
    s
}

fn benches(c: &mut Criterion) {
    let text = csv_500();
    let annotations = Annotations::from_csv_str(&text).expect("benchmark CSV parses");
    assert_eq!(annotations.rows.len(), 500);
    let mut group = c.benchmark_group("annotation_500_rows");
    group.bench_function("parse_csv", |b| {
        b.iter(|| Annotations::from_csv_str(black_box(&text)).expect("parses"))
    });
    group.bench_function("validate", |b| b.iter(|| black_box(&annotations).validate()));
    group.bench_function("write_csv", |b| {
        b.iter(|| black_box(&annotations).to_csv_string().expect("writes"))
    });
    let json = annotations.to_json_string().expect("JSON");
    group.bench_function("parse_json", |b| {
        b.iter(|| Annotations::from_json_str(black_box(&json)).expect("parses"))
    });
    group.bench_function("stats", |b| b.iter(|| black_box(&annotations).stats()));
    group.finish();
}

criterion_group!(annotation, benches);
criterion_main!(annotation);
