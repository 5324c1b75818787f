//! Scaling measurements of the plausibility metrics, and the scenes the peer comparison
//! (`benches/peers/`) runs on.
//!
//! ```text
//! scaling gen --kind boxes|fixtures|mesh8k --n N --out DIR [--fixtures DIR]
//!     writes DIR/scene_<N>.json (sceneState), DIR/assets/<name>.glb (boxes, mesh8k) and
//!     DIR/peers_<N>.json: the scene as read back by sceneeval-io (object-frame meshes of each
//!     distinct asset, world poses, floors), the exact input the Python peers load.
//! scaling run --scene FILE --assets PREFIX=DIR [--metric NAME|all|evaluate] [--repeat K]
//!     [--threads T] [--resolution M] [--depth verdict|colliding|all]
//!     reads the scene, runs the metric K times (minimum kept) on T rayon threads and prints
//!     one JSON line: seconds per metric (the minimum, and the first run's, which also builds
//!     the per-mesh tables), the scene's load time, and the process's peak resident memory
//!     (VmHWM) before and after the metrics.
//! ```
//!
//! Run through `benches/peers/run.sh`, which lists every command of `docs/performance.md`.

// A measurement binary prints its results and stops on a set-up failure.
#![allow(clippy::print_stdout, clippy::print_stderr, clippy::expect_used)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use sceneeval_geom::conventions::object_from_asset;
use sceneeval_geom::{Mesh, Real, Vector3};
use sceneeval_io::{AssetLibrary, GlbMesh, ReadOptions, read_scene_state, write_glb, write_scene_state};
use sceneeval_plausibility::{
    FunctionalSidePriors, FunctionalSidesSource, PlausibilityParams, Resolution, Sources, SupportTypePriors,
    SupportTypeSource, accessibility, collision_with_work, evaluate, navigability, opening_clearance,
    out_of_bounds, support,
};
use sceneeval_scene::Scene;
use sceneeval_test_support::scenes::{AssetSet, box_set, mesh8k_set, scaling_scene};
use serde_json::{Value, json};

const METRICS: [&str; 6] = [
    "collision",
    "support",
    "navigability",
    "accessibility",
    "out_of_bounds",
    "opening_clearance",
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("gen") => generate(&args[1..]),
        Some("run") => run(&args[1..]),
        _ => Err("usage: scaling gen|run ... (see the source's header)".to_owned()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scaling: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `--name value` pairs.
fn options(args: &[String]) -> Result<HashMap<String, String>, String> {
    let mut out = HashMap::new();
    let mut it = args.iter();
    while let Some(k) = it.next() {
        let name = k
            .strip_prefix("--")
            .ok_or_else(|| format!("expected --option, got {k}"))?;
        let value = it.next().ok_or_else(|| format!("--{name} needs a value"))?;
        out.insert(name.to_owned(), value.clone());
    }
    Ok(out)
}

fn get<'a>(o: &'a HashMap<String, String>, k: &str) -> Result<&'a str, String> {
    o.get(k)
        .map(String::as_str)
        .ok_or_else(|| format!("missing --{k}"))
}

/// The fixture assets as a set: a dining table, a wardrobe, a table lamp and a painting.
fn fixture_set(dir: &Path) -> Result<AssetSet, String> {
    let lib = AssetLibrary::from_specs(&[format!("fixture={}", dir.display())]).map_err(|e| e.to_string())?;
    let load = |name: &str| -> Result<(String, Arc<Mesh>), String> {
        let mesh = lib
            .mesh(&format!("fixture.{name}"), &Vector3::repeat(1.0))
            .map_err(|e| e.to_string())?;
        Ok((name.to_owned(), mesh))
    };
    Ok(AssetSet {
        kind: "fixtures".into(),
        prefix: "fixture".into(),
        table: load("dining_table")?,
        cabinet: load("wardrobe")?,
        lamp: load("table_lamp")?,
        painting: load("painting")?,
    })
}

fn generate(args: &[String]) -> Result<(), String> {
    let o = options(args)?;
    let n: usize = get(&o, "n")?.parse().map_err(|e| format!("--n: {e}"))?;
    let out = PathBuf::from(get(&o, "out")?);
    let set = match get(&o, "kind")? {
        "boxes" => box_set(),
        "mesh8k" => mesh8k_set(),
        "fixtures" => fixture_set(Path::new(
            o.get("fixtures").map_or("fixtures/assets", String::as_str),
        ))?,
        other => return Err(format!("unknown --kind {other}")),
    };
    let assets = out.join("assets");
    std::fs::create_dir_all(&assets).map_err(|e| format!("{}: {e}", assets.display()))?;
    if set.prefix == "bench" {
        // Asset files are y up, front +z: the inverse of the object-from-asset rotation.
        let to_asset = object_from_asset().inverse();
        for (name, mesh) in [&set.table, &set.cabinet, &set.lamp, &set.painting] {
            let positions = mesh
                .vertices()
                .iter()
                .map(|p| {
                    let q = to_asset * p;
                    [q.x as f32, q.y as f32, q.z as f32]
                })
                .collect();
            let indices = mesh.triangles().iter().flatten().copied().collect();
            write_glb(
                &assets.join(format!("{name}.glb")),
                &[GlbMesh::new(name.clone(), positions, indices)],
            )
            .map_err(|e| e.to_string())?;
        }
    }
    let scene = scaling_scene(n, &set);
    let path = out.join(format!("scene_{n}.json"));
    write_scene_state(&scene, &path).map_err(|e| e.to_string())?;
    // Read it back as the CLI will, and hand exactly that to the peers.
    let spec = if set.prefix == "bench" {
        format!("bench={}", assets.display())
    } else {
        format!(
            "fixture={}",
            o.get("fixtures").map_or("fixtures/assets", String::as_str)
        )
    };
    let lib = AssetLibrary::from_specs(&[spec]).map_err(|e| e.to_string())?;
    let read = read_scene_state(&path, &lib, &ReadOptions::default()).map_err(|e| e.to_string())?;
    let manifest = peers_manifest(&read, &set.kind);
    let mpath = out.join(format!("peers_{n}.json"));
    std::fs::write(&mpath, manifest.to_string()).map_err(|e| format!("{}: {e}", mpath.display()))?;
    println!(
        "{}",
        json!({"scene": path, "peers": mpath, "objects": read.objects().len(), "kind": set.kind})
    );
    Ok(())
}

/// The scene as the peers load it: each distinct mesh once (object frame), every object's
/// world pose (row-major 4 x 4), category, and the floor polygons with their heights.
fn peers_manifest(scene: &Scene, kind: &str) -> Value {
    let sources = Sources::default();
    let mut meshes: Vec<Value> = Vec::new();
    let mut slot: HashMap<*const Mesh, usize> = HashMap::new();
    let objects: Vec<Value> = scene
        .objects()
        .iter()
        .map(|o| {
            let k = *slot.entry(Arc::as_ptr(o.mesh())).or_insert_with(|| {
                let m = o.mesh();
                meshes.push(json!({
                    "vertices": m.vertices().iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
                    "triangles": m.triangles(),
                }));
                meshes.len() - 1
            });
            let h = o.pose().to_homogeneous();
            let rows: Vec<Real> = (0..4).flat_map(|r| (0..4).map(move |c| h[(r, c)])).collect();
            let support = sources.support_types.support_type(scene, o).map(|a| a.value);
            let sides = sources
                .functional_sides
                .functional_sides(scene, o)
                .map(|a| a.value)
                .unwrap_or_default();
            json!({
                "id": o.id().as_str(),
                "mesh": k,
                "pose": rows,
                "category": o.category(),
                "support": support,
                "sides": sides,
            })
        })
        .collect();
    let floors: Vec<Value> = scene
        .rooms()
        .iter()
        .map(|r| {
            json!({
                "polygon": r.floor().points().iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
                "z": r.floor_z(),
            })
        })
        .collect();
    json!({"kind": kind, "meshes": meshes, "objects": objects, "floors": floors})
}

/// Peak resident memory of this process so far, megabytes (Linux `VmHWM`).
fn peak_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn run(args: &[String]) -> Result<(), String> {
    let o = options(args)?;
    let path = PathBuf::from(get(&o, "scene")?);
    let specs: Vec<&str> = get(&o, "assets")?.split(',').collect();
    let metric = o.get("metric").map_or("all", String::as_str);
    let repeat: usize = o
        .get("repeat")
        .map_or(Ok(1), |r| r.parse())
        .map_err(|e| format!("--repeat: {e}"))?;
    let threads: usize = o
        .get("threads")
        .map_or(Ok(1), |t| t.parse())
        .map_err(|e| format!("--threads: {e}"))?;
    let mut params = PlausibilityParams::default();
    if let Some(d) = o.get("depth") {
        params.collision.depth_search =
            serde_json::from_value(json!(d)).map_err(|e| format!("--depth: {e}"))?;
    }
    if let Some(m) = o.get("resolution") {
        let m: Real = m.parse().map_err(|e| format!("--resolution: {e}"))?;
        params.navigability.resolution = Resolution::MetresPerPixel(m);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())?;
    let t = Instant::now();
    let lib = AssetLibrary::from_specs(&specs).map_err(|e| e.to_string())?;
    let scene = read_scene_state(&path, &lib, &ReadOptions::default()).map_err(|e| e.to_string())?;
    let load = t.elapsed().as_secs_f64();
    let after_load = peak_mb();
    let names: Vec<&str> = match metric {
        "all" => METRICS.to_vec(),
        "evaluate" => vec!["evaluate"],
        one => vec![one],
    };
    let mut times = serde_json::Map::new();
    let mut first_times = serde_json::Map::new();
    for name in names {
        let mut best = f64::INFINITY;
        for k in 0..repeat.max(1) {
            let t = Instant::now();
            pool.install(|| run_metric(name, &scene, &params))?;
            let s = t.elapsed().as_secs_f64();
            if k == 0 {
                // The first run also builds the per-mesh tables (inside tests, hierarchies).
                first_times.insert(name.to_owned(), json!(s));
            }
            best = best.min(s);
        }
        times.insert(name.to_owned(), json!(best));
    }
    println!(
        "{}",
        json!({
            "scene": path,
            "objects": scene.objects().len(),
            "triangles": scene.objects().iter().map(|o| o.mesh().triangles().len()).sum::<usize>(),
            "threads": threads,
            "load_s": load,
            "seconds": times,
            "first_seconds": first_times,
            "peak_mb_after_load": after_load,
            "peak_mb": peak_mb(),
        })
    );
    Ok(())
}

fn run_metric(name: &str, s: &Scene, p: &PlausibilityParams) -> Result<(), String> {
    let e = |e: sceneeval_plausibility::PlausibilityError| e.to_string();
    match name {
        "collision" => {
            let (r, w) = collision_with_work(s, &p.collision).map_err(e)?;
            if std::env::var_os("SCALING_WORK").is_some() {
                eprintln!(
                    "collision: {} broad-phase box tests, {} candidate pairs, {} contacts ({} colliding), {} point queries, at most {} per pair",
                    w.broad_phase_box_tests,
                    w.candidate_pairs,
                    r.contacts.len(),
                    r.num_colliding_pairs,
                    w.point_queries,
                    w.max_pair_queries
                );
            }
        }
        "support" => drop(support(s, &p.support, &SupportTypePriors::default()).map_err(e)?),
        "navigability" => drop(navigability(s, &p.navigability).map_err(e)?),
        "accessibility" => {
            drop(accessibility(s, &p.accessibility, &FunctionalSidePriors::default()).map_err(e)?)
        }
        "out_of_bounds" => {
            let r = out_of_bounds(s, &p.out_of_bounds).map_err(e)?;
            if std::env::var_os("SCALING_WORK").is_some() {
                let crossing: usize = r
                    .objects
                    .iter()
                    .zip(s.objects())
                    .filter(|(b, _)| b.ratio_in_bounds < 1.0)
                    .map(|(_, o)| o.mesh().triangles().len())
                    .sum();
                eprintln!(
                    "out_of_bounds: {} objects out, triangles of objects not wholly in bounds: {crossing}",
                    r.num_out
                );
            }
        }
        "opening_clearance" => drop(opening_clearance(s, &p.opening_clearance).map_err(e)?),
        "evaluate" => drop(evaluate(s, p, &Sources::default()).map_err(e)?),
        other => return Err(format!("unknown metric {other}")),
    }
    Ok(())
}
