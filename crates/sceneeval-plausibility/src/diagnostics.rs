//! Diagnostic PNGs: the navigability occupancy map, the access strips and the occlusion maps
//! of blocked openings.

use std::path::{Path, PathBuf};

use image::{ImageFormat, Rgb, RgbImage};
use sceneeval_scene::Scene;

use crate::clearance::{OcclusionMap, OpeningFrame, intruding_parts};
use crate::raster::{Grid, Storage, check_raster};
use crate::{Deadline, PlausibilityError, PlausibilityParams, Sources};

/// The stage named when the deadline passes while the images are drawn.
const STAGE: &str = "diagnostics";

const OFF_FLOOR: Rgb<u8> = Rgb([40, 40, 40]);
const BLOCKED: Rgb<u8> = Rgb([200, 70, 60]);
const FREE_OTHER: Rgb<u8> = Rgb([240, 200, 60]);
const FREE_LARGEST: Rgb<u8> = Rgb([70, 170, 90]);
const FLOOR: Rgb<u8> = Rgb([205, 205, 205]);
const FOOTPRINT: Rgb<u8> = Rgb([140, 105, 75]);
const STRIP_FREE: Rgb<u8> = Rgb([60, 120, 220]);
const STRIP_BLOCKED: Rgb<u8> = Rgb([220, 60, 200]);
const CLEAR: Rgb<u8> = Rgb([235, 235, 235]);
const OCCLUDED: Rgb<u8> = Rgb([220, 50, 50]);

/// Writes the diagnostic images of `scene` into `dir` (created if needed) and returns their
/// paths:
///
/// - `navigability.png`: the occupancy raster of the navigability metric, north up; off-floor
///   dark grey, blocked floor red, the largest free region green, other free regions yellow.
/// - `accessibility.png`: floor light grey, obstructing footprints brown, and each functional
///   side's access strip blue where free and magenta where blocked (on the navigability grid).
/// - `opening_<opening>_<side>.png` for every blocked side of a door or window: the opening
///   seen from the checked side, occluded pixels red.
///
/// The bytes are deterministic (same scene and parameters, same files). Each file is written
/// through a unique temporary file and an atomic rename. The metrics behind the images run
/// under `deadline` (a scene's time budget covers its images too), which is also checked
/// between the images and per footprint and opening drawn.
///
/// # Errors
/// The metrics' errors (bad parameters, [`PlausibilityError::DeadlineExceeded`] naming the
/// stage, ...), [`PlausibilityError::Io`] when a file cannot be written,
/// [`PlausibilityError::Image`] when a PNG cannot be encoded.
pub fn write_diagnostics(
    scene: &Scene,
    params: &PlausibilityParams,
    sources: &Sources,
    dir: &Path,
    deadline: &Deadline,
) -> Result<Vec<PathBuf>, PlausibilityError> {
    crate::navigability::validate(&params.navigability)?;
    std::fs::create_dir_all(dir).map_err(|source| PlausibilityError::Io {
        path: dir.to_owned(),
        source,
    })?;
    let mut written = Vec::new();
    let infos = crate::objects::object_infos_within(scene, deadline, STAGE)?;
    let map = crate::navigability::build_map(scene, &params.navigability, &infos, deadline)
        .map_err(in_diagnostics)?
        .0;
    let grid = map.grid;
    // The images hold a value per pixel, unlike the navigability raster's runs.
    check_raster("diagnostics", grid.width, grid.height, Storage::Dense)?;
    deadline.check(STAGE)?;
    let (run_labels, sizes) = map.components();
    let largest = (0..sizes.len()).max_by(|&a, &b| sizes[a].cmp(&sizes[b]).then(b.cmp(&a)));
    // Per pixel: on a floor, and the free region's label (u32::MAX where not free).
    let mut on_floor = vec![false; grid.len()];
    let mut labels = vec![u32::MAX; grid.len()];
    for j in 0..grid.height {
        for run in map.floor.row(j) {
            for i in run[0]..run[1] {
                on_floor[grid.index(i as usize, j)] = true;
            }
        }
        let base = map.free.row_offset(j);
        for (k, run) in map.free.row(j).iter().enumerate() {
            for i in run[0]..run[1] {
                labels[grid.index(i as usize, j)] = run_labels[base + k];
            }
        }
    }
    let nav = image_from(&grid, |k| {
        if !on_floor[k] {
            OFF_FLOOR
        } else if labels[k] == u32::MAX {
            BLOCKED
        } else if Some(labels[k] as usize) == largest {
            FREE_LARGEST
        } else {
            FREE_OTHER
        }
    });
    written.push(save(&nav, &dir.join("navigability.png"))?);

    let pieces = crate::accessibility::scene_floor_pieces(scene);
    let acc = crate::accessibility::accessibility_with(
        scene,
        &params.accessibility,
        sources.functional_sides.as_ref(),
        &infos,
        &pieces,
        deadline,
    )
    .map_err(in_diagnostics)?;
    let mut occupied = vec![false; grid.len()];
    let p = &params.accessibility;
    for info in infos
        .iter()
        .filter(|i| i.obstructs(p.height_cutoff_m, p.walkable_height_m))
    {
        deadline.check(STAGE)?;
        grid.for_convex_within(&info.footprint, 0.0, |k| occupied[k] = true);
    }
    let mut colours: Vec<Rgb<u8>> = (0..grid.len())
        .map(|k| match (on_floor[k], occupied[k]) {
            (false, _) => OFF_FLOOR,
            (true, true) => FOOTPRINT,
            (true, false) => FLOOR,
        })
        .collect();
    for side in acc.objects.iter().flat_map(|o| &o.sides) {
        deadline.check(STAGE)?;
        grid.for_convex_within(&side.strip, 0.0, |k| {
            colours[k] = if on_floor[k] && !occupied[k] {
                STRIP_FREE
            } else {
                STRIP_BLOCKED
            };
        });
    }
    let acc_img = image_from(&grid, |k| colours[k]);
    written.push(save(&acc_img, &dir.join("accessibility.png"))?);

    let clearance =
        crate::clearance::opening_clearance_with(scene, &params.opening_clearance, &infos, deadline)
            .map_err(in_diagnostics)?;
    let candidates = crate::clearance::Candidates::new(scene, &infos, &params.opening_clearance);
    for (room, wall, opening) in scene.openings() {
        let Some(report) = clearance
            .openings
            .iter()
            .find(|o| o.opening == opening.id && o.wall == wall.id() && o.room == room.id().as_str())
        else {
            continue;
        };
        for side in report.sides.iter().filter(|s| s.blocked) {
            let frame = OpeningFrame::new(
                wall,
                opening,
                side.side,
                side.depth,
                params.opening_clearance.touch_tolerance_m,
            );
            let occ = OcclusionMap::new(&frame, params.opening_clearance.pixels_per_m)?;
            let mut mask = vec![false; occ.nu * occ.nw];
            for (_, parts) in intruding_parts(scene, &candidates, &frame) {
                for part in &parts {
                    deadline.check(STAGE)?;
                    occ.fill(part, |i| mask[i] = true);
                }
            }
            let img = RgbImage::from_fn(occ.nu as u32, occ.nw as u32, |x, y| {
                let j = occ.nw - 1 - y as usize;
                if mask[j * occ.nu + x as usize] {
                    OCCLUDED
                } else {
                    CLEAR
                }
            });
            let side_name = match side.side {
                crate::OpeningSide::Room => "room",
                crate::OpeningSide::Far => "far",
            };
            let name = format!("opening_{}_{side_name}.png", sanitize(&report.opening));
            written.push(save(&img, &dir.join(name))?);
        }
    }
    Ok(written)
}

/// A deadline error of a metric run for the images, as the diagnostics stage's (the metric
/// itself ran, or will run, under its own name).
fn in_diagnostics(e: PlausibilityError) -> PlausibilityError {
    match e {
        PlausibilityError::DeadlineExceeded { budget_seconds, .. } => PlausibilityError::DeadlineExceeded {
            stage: STAGE,
            budget_seconds,
        },
        e => e,
    }
}

/// An image of the grid, north (highest y) up.
fn image_from(grid: &Grid, colour: impl Fn(usize) -> Rgb<u8>) -> RgbImage {
    RgbImage::from_fn(grid.width as u32, grid.height as u32, |x, y| {
        let j = grid.height - 1 - y as usize;
        colour(grid.index(x as usize, j))
    })
}

/// Encodes `img` as PNG and writes it atomically ([`sceneeval_files::write_atomic`]): a full
/// disk or a second writer never leaves an empty or partial image.
fn save(img: &RgbImage, path: &Path) -> Result<PathBuf, PlausibilityError> {
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), ImageFormat::Png)
        .map_err(|e| PlausibilityError::Image {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    sceneeval_files::write_atomic(path, &bytes).map_err(|source| PlausibilityError::Io {
        path: path.to_owned(),
        source,
    })?;
    Ok(path.to_owned())
}

/// A file-name-safe form of an id: characters other than ASCII letters, digits, `-`, `_` and
/// `.` become `_`.
fn sanitize(id: &str) -> String {
    id.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitizes_ids() {
        assert_eq!(sanitize("r0_wall_0/door 1"), "r0_wall_0_door_1");
    }
}
