//! The stability metric on twelve small rooms (`fixtures/scenes/scene_0.json` to
//! `scene_11.json`: eleven with the fixtures' furniture meshes, one of boxes), every weld
//! variant, decomposition included: the measurement of the issue's target (the SceneSmith
//! fork takes about 1,800 s for twelve small rooms over its four variants).
//!
//! ```text
//! stability-rooms [--fixtures DIR] [--heavy] [--cache DIR] [--threads T] [--time-step S] [--verbose]
//! stability-rooms [--fixtures DIR] [--heavy] --export-fork DIR
//! stability-rooms --scaling boxes|mesh8k N
//! ```
//!
//! Prints one line per scene and variant (objects, free, unstable, simulated time, steps,
//! seconds) and the totals: the first pass over the four variants with an empty
//! decomposition cache (`--cache DIR`: an empty folder; default in memory), then a second pass
//! over the same variants reusing it. Support types are the ones the scene files state.
//!
//! `--heavy` refurnishes five of the twelve rooms with generated furniture of 9,600 to 40,048
//! triangles (`sceneeval_benches::heavy`): the rooms "with real furniture meshes" of the
//! issue's target. `--export-fork DIR` writes, instead of evaluating, what the SceneSmith fork's
//! metric needs for each room (`DIR/scene_N/manifest.json`: the scene file, each object's
//! world-space mesh as an OBJ file and its support type), read by `benches/fork/
//! run_fork_stability.py`.
//!
//! `--scaling KIND N` instead evaluates the benchmark's scaling room of `N` objects
//! (`sceneeval_test_support::scenes::scaling_scene`, support types from the category tables)
//! once with an empty cache and once warm, and prints what the simulation did (simulated time,
//! steps, free, unstable and welded objects, pieces) with both times: the figures behind the
//! `physics/simulate` benchmark.

#![allow(clippy::print_stdout, clippy::print_stderr, clippy::expect_used)]

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_physics::{DecompositionCache, Stability, StabilityParams, WeldMode};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stability-rooms: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut fixtures = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures"));
    let mut cache_dir = None;
    let mut threads = None;
    let mut verbose = false;
    let mut scaling = None;
    let mut heavy = false;
    let mut export = None;
    let mut time_step_s = StabilityParams::default().time_step_s;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--fixtures" => fixtures = PathBuf::from(value()?),
            "--cache" => cache_dir = Some(PathBuf::from(value()?)),
            "--verbose" => verbose = true,
            "--heavy" => heavy = true,
            "--export-fork" => export = Some(PathBuf::from(value()?)),
            "--time-step" => time_step_s = value()?.parse::<f64>().map_err(|e| e.to_string())?,
            "--scaling" => {
                let kind = value()?;
                let n = args
                    .next()
                    .ok_or("--scaling needs a kind and a count")?
                    .parse::<usize>()
                    .map_err(|e| e.to_string())?;
                scaling = Some((kind, n));
            }
            "--threads" => threads = Some(value()?.parse::<usize>().map_err(|e| e.to_string())?),
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    if let Some(t) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| e.to_string())?;
    }
    if let Some((kind, n)) = scaling {
        return scaling_room(&kind, n);
    }
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(fixtures.join("assets")));
    let load = Instant::now();
    let scenes = (0..12)
        .map(|n| {
            let path = fixtures.join(format!("scenes/scene_{n}.json"));
            read_scene_state(&path, &library, &ReadOptions::default())
                .map_err(|e| format!("{}: {e}", path.display()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    println!("loaded 12 scenes in {:.3} s", load.elapsed().as_secs_f64());
    let scenes = if heavy {
        let t = Instant::now();
        let (scenes, replaced) = sceneeval_benches::heavy::heavy_rooms(&scenes).map_err(|e| e.to_string())?;
        let triangles: usize = scenes
            .iter()
            .flat_map(|s| s.objects())
            .map(|o| o.mesh().triangles().len())
            .sum();
        println!(
            "refurnished rooms {:?}: {replaced} objects replaced, {triangles} triangles in the twelve rooms, in {:.3} s",
            sceneeval_benches::heavy::HEAVY_ROOMS,
            t.elapsed().as_secs_f64()
        );
        scenes
    } else {
        scenes
    };
    if let Some(dir) = export {
        return export_for_fork(&fixtures, &scenes, &dir);
    }
    let cache = match cache_dir {
        Some(d) => DecompositionCache::on_disk(d).map_err(|e| e.to_string())?,
        None => DecompositionCache::in_memory(),
    };
    for pass in ["cold cache", "warm cache"] {
        let start = Instant::now();
        let cpu = cpu_seconds();
        for weld in WeldMode::ALL {
            let stability = Stability::new(StabilityParams {
                weld,
                time_step_s,
                ..StabilityParams::default()
            })
            .map_err(|e| e.to_string())?;
            for scene in &scenes {
                let support: Vec<_> = scene.objects().iter().map(|o| o.support_type()).collect();
                let t = Instant::now();
                let r = stability
                    .evaluate(scene, &support, &cache, &sceneeval_scene::Deadline::none())
                    .map_err(|e| format!("{}: {e}", scene.name().unwrap_or("?")))?;
                let unstable: Vec<&str> = r
                    .objects
                    .iter()
                    .filter(|o| !o.stable)
                    .map(|o| o.id.as_str())
                    .collect();
                let pieces: usize = r.objects.iter().map(|o| o.body.pieces).sum();
                println!(
                    "{pass:10} {:13} {:9}: {:3} objects, {:3} free, {:2} unstable, {:4} pieces, {:.3} s simulated in {:5} steps, {:.3} s  {:?}",
                    weld.name(),
                    scene.name().unwrap_or("?"),
                    r.objects.len(),
                    r.num_free,
                    r.num_unstable,
                    pieces,
                    r.simulated_s,
                    r.steps,
                    t.elapsed().as_secs_f64(),
                    unstable
                );
                if verbose {
                    for o in r
                        .objects
                        .iter()
                        .filter(|o| o.displacement_m > 1e-3 || o.rotation_rad > 1e-2)
                    {
                        println!(
                            "    {:28} moved {:.4} m, turned {:.4} rad, welded {:?}, {:?}, {:?}",
                            o.id.as_str(),
                            o.displacement_m,
                            o.rotation_rad,
                            o.weld_reason,
                            o.interpenetration,
                            o.body
                        );
                    }
                }
            }
        }
        let s = cache.stats();
        let cpu = cpu_seconds().zip(cpu).map_or(f64::NAN, |(b, a)| b - a);
        println!(
            "{pass}: 12 rooms x 4 variants in {:.3} s, {cpu:.2} s of CPU (decomposed {}, memory hits {}, disk hits {})",
            start.elapsed().as_secs_f64(),
            s.decomposed,
            s.memory_hits,
            s.disk_hits
        );
    }
    Ok(())
}

/// Writes `dir/scene_N/manifest.json` and `dir/scene_N/objects/K.obj` for each room: the
/// input of `benches/fork/run_fork_stability.py`, which loads them as the fork's `Scene` does
/// (world-space meshes, architecture from the scene file).
fn export_for_fork(
    fixtures: &std::path::Path,
    scenes: &[sceneeval_scene::Scene],
    dir: &std::path::Path,
) -> Result<(), String> {
    use std::fmt::Write as _;
    for (n, scene) in scenes.iter().enumerate() {
        let room = dir.join(format!("scene_{n}"));
        std::fs::create_dir_all(room.join("objects")).map_err(|e| format!("{}: {e}", room.display()))?;
        let mut objects = Vec::new();
        for (k, o) in scene.objects().iter().enumerate() {
            let mut obj = String::new();
            for p in o.mesh().vertices() {
                let w = o.pose() * p;
                let _ = writeln!(obj, "v {} {} {}", w.x, w.y, w.z);
            }
            for t in o.mesh().triangles() {
                let _ = writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
            }
            let name = format!("objects/{k}.obj");
            write_file(&room.join(&name), obj.as_bytes())?;
            objects.push(serde_json::json!({
                "id": o.id().as_str(),
                "mesh": name,
                "triangles": o.mesh().triangles().len(),
                "support": o.support_type().map(|s| s.name()),
            }));
        }
        let scene_file = std::path::absolute(fixtures.join(format!("scenes/scene_{n}.json")))
            .map_err(|e| e.to_string())?;
        let manifest = serde_json::json!({ "scene": scene_file, "objects": objects });
        let text = serde_json::to_string_pretty(&manifest).map_err(|e| e.to_string())?;
        write_file(&room.join("manifest.json"), text.as_bytes())?;
    }
    println!("wrote {} rooms under {}", scenes.len(), dir.display());
    Ok(())
}

/// Writes through a temporary name in the same folder and an atomic rename.
fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<(), String> {
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

fn scaling_room(kind: &str, n: usize) -> Result<(), String> {
    use sceneeval_plausibility::{SupportTypePriors, SupportTypeSource};
    use sceneeval_test_support::scenes::{box_set, mesh8k_set, scaling_scene};
    let set = match kind {
        "boxes" => box_set(),
        "mesh8k" => mesh8k_set(),
        _ => return Err(format!("unknown kind {kind}: boxes or mesh8k")),
    };
    let scene = scaling_scene(n, &set);
    let priors = SupportTypePriors::default();
    let support: Vec<_> = scene
        .objects()
        .iter()
        .map(|o| priors.support_type(&scene, o).map(|a| a.value))
        .collect();
    let stability = Stability::new(StabilityParams::default()).map_err(|e| e.to_string())?;
    let cache = DecompositionCache::in_memory();
    for pass in ["cold cache", "warm cache"] {
        let t = Instant::now();
        let cpu = cpu_seconds();
        let r = stability
            .evaluate(&scene, &support, &cache, &sceneeval_scene::Deadline::none())
            .map_err(|e| e.to_string())?;
        let pieces: usize = r.objects.iter().map(|o| o.body.pieces).sum();
        let cpu = cpu_seconds().zip(cpu).map_or(f64::NAN, |(b, a)| b - a);
        println!(
            "{kind} {n} {pass}: {:.3} s, {cpu:.2} s of CPU; simulated {:.3} s in {} steps; {} free, {} unstable, {} welded; {pieces} pieces",
            t.elapsed().as_secs_f64(),
            r.simulated_s,
            r.steps,
            r.num_free,
            r.num_unstable,
            r.objects.len() - r.num_free,
        );
    }
    Ok(())
}

/// CPU time (user + system) this process has used so far, seconds (Linux `/proc/self/stat`,
/// at the usual 100 clock ticks per second): on a loaded machine the honest figure next to
/// the wall time.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which ends with the last ')'): utime and stime are the
    // 12th and 13th.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}
