//! `sceneeval inspect SCENE.json --assets PREFIX=DIR ...`: load a sceneState file and print its
//! objects (id, model id, category, OBB centre, size, yaw, stated support type), rooms, walls
//! and openings, as aligned tables or (`--format json`, alias `--json`) as one JSON document.
//!
//! A scene that fails to load is an error: `main` prints its chain (the file, the JSON
//! pointer, the asset) and the process exits with status 1.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::geom::Real;
use sceneeval::inspect::{ObjectInfo, RoomInfo, SceneInfo};
use sceneeval::io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval::scene::{Scene, SupportType};
use serde::Serialize;

/// Arguments of `sceneeval inspect`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sceneState JSON file.
    pub scene: PathBuf,
    /// Where the assets of a model id prefix live: `PREFIX=DIR` (layout from the prefix:
    /// `3dfModel` 3D-FUTURE, `objaverse` Objathor, `fpModel` HSSD, `layoutvlm-objaverse`
    /// LayoutVLM, anything else a plain folder of `ID.glb`/`ID.gltf`/`ID.obj`) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of `3d-future`, `objathor`, `hssd`, `layoutvlm`,
    /// `idesign`, `scene-agent`, `plain`. Repeatable.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// `--format json`: one JSON document (`scene`, `objects`, `rooms` with their walls and
    /// openings) instead of tables.
    #[command(flatten)]
    pub format: crate::format::FormatArgs,
    /// Refuse a scene file with keys the sceneState format does not have (a misspelt key is
    /// read as absent) instead of warning about each.
    #[arg(long)]
    pub strict: bool,
}

/// Reads the sceneState file `scene` with the asset folders `assets` (`--assets` specs),
/// refusing keys the format does not have when `strict`: how `inspect` and `render` load the
/// scene they are given. The asset library comes back too (the renderer draws from it).
pub(crate) fn load_scene(
    scene: &Path,
    assets: &[String],
    strict: bool,
) -> anyhow::Result<(AssetLibrary, Scene)> {
    let library = AssetLibrary::from_specs(assets).context("invalid --assets")?;
    let loaded = read_scene_state(scene, &library, &ReadOptions::default().with_strict(strict))
        .with_context(|| format!("cannot load scene {}", scene.display()))?;
    Ok((library, loaded))
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let (library, scene) = load_scene(&args.scene, &args.assets, args.strict)?;
    tracing::info!(
        objects = scene.objects().len(),
        rooms = scene.rooms().len(),
        assets_read = library.files_read(),
        "scene loaded"
    );
    let report = Report::new(&args.scene, &scene);
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    if args.format.json() {
        serde_json::to_writer_pretty(&mut out, &report).context("writing JSON")?;
        writeln!(out)?;
    } else {
        report.write_tables(&mut out)?;
    }
    out.flush().context("writing to standard output")?;
    Ok(ExitCode::SUCCESS)
}

/// The JSON document of `inspect --json`: the scene's name, the file, and the facade's
/// [`SceneInfo`] objects and rooms. Lengths in metres, angles in radians.
#[derive(Debug, Serialize)]
struct Report<'a> {
    /// The scene's name (the file stem).
    scene: Option<&'a str>,
    file: &'a Path,
    objects: Vec<ObjectInfo<'a>>,
    rooms: Vec<RoomInfo<'a>>,
}

impl<'a> Report<'a> {
    fn new(file: &'a Path, scene: &'a Scene) -> Self {
        let info = SceneInfo::new(scene);
        Report {
            scene: info.scene,
            file,
            objects: info.objects,
            rooms: info.rooms,
        }
    }

    /// The objects table of [`Report::write_tables`].
    fn write_objects(&self, out: &mut impl Write) -> io::Result<()> {
        writeln!(
            out,
            "\nObjects (centre and size in metres, yaw in degrees; size = width x depth x height; \
             asset front = the front the file declares in the object's frame, turned to -y)"
        )?;
        let rows = self
            .objects
            .iter()
            .map(|o| {
                vec![
                    o.id.to_owned(),
                    o.model_id
                        .unwrap_or(if o.is_box { "(box)" } else { "-" })
                        .to_owned(),
                    o.category.unwrap_or("-").to_owned(),
                    num(o.center[0]),
                    num(o.center[1]),
                    num(o.center[2]),
                    format!("{} x {} x {}", num(o.size[0]), num(o.size[1]), num(o.size[2])),
                    format!("{:.1}", o.yaw.to_degrees()),
                    o.asset_front.map_or_else(|| "-".to_owned(), axis_name),
                    o.support_type.map_or("-", SupportType::name).to_owned(),
                ]
            })
            .collect();
        table(
            out,
            &[
                "id",
                "model id",
                "category",
                "x",
                "y",
                "z",
                "size",
                "yaw",
                "asset front",
                "support",
            ],
            &[false, false, false, true, true, true, false, true, false, false],
            rows,
        )
    }

    fn write_tables(&self, out: &mut impl Write) -> io::Result<()> {
        let walls: usize = self.rooms.iter().map(|r| r.walls.len()).sum();
        let openings: usize = self
            .rooms
            .iter()
            .flat_map(|r| &r.walls)
            .map(|w| w.openings.len())
            .sum();
        writeln!(
            out,
            "scene {} ({}): {}, {}, {}, {}",
            self.scene.unwrap_or("-"),
            self.file.display(),
            count(self.objects.len(), "object"),
            count(self.rooms.len(), "room"),
            count(walls, "wall"),
            count(openings, "opening"),
        )?;

        self.write_objects(out)?;

        writeln!(out, "\nRooms")?;
        let rows = self
            .rooms
            .iter()
            .map(|r| {
                vec![
                    r.id.to_owned(),
                    r.kind.unwrap_or("-").to_owned(),
                    r.floor_id.to_owned(),
                    num(r.floor_z),
                    r.ceiling_z.map_or_else(|| "-".to_owned(), num),
                    num(r.floor_area),
                    r.walls.len().to_string(),
                ]
            })
            .collect();
        table(
            out,
            &[
                "id",
                "type",
                "floor id",
                "floor z",
                "ceiling z",
                "area m2",
                "walls",
            ],
            &[false, false, false, true, true, true, true],
            rows,
        )?;

        writeln!(
            out,
            "\nWalls (start and end of the inner face; inward = normal into the room)"
        )?;
        let rows = self
            .rooms
            .iter()
            .flat_map(|r| r.walls.iter().map(move |w| (r, w)))
            .map(|(r, w)| {
                vec![
                    r.id.to_owned(),
                    w.id.to_owned(),
                    format!("({}, {})", num(w.start[0]), num(w.start[1])),
                    format!("({}, {})", num(w.end[0]), num(w.end[1])),
                    num(w.length),
                    num(w.base_z),
                    num(w.height),
                    num(w.thickness),
                    format!("({}, {})", num(w.inward_normal[0]), num(w.inward_normal[1])),
                    w.openings.len().to_string(),
                ]
            })
            .collect();
        table(
            out,
            &[
                "room",
                "id",
                "start",
                "end",
                "length",
                "base z",
                "height",
                "thickness",
                "inward",
                "openings",
            ],
            &[false, false, false, false, true, true, true, true, false, true],
            rows,
        )?;

        writeln!(
            out,
            "\nOpenings (along the wall from its start; height above its base)"
        )?;
        let rows = self
            .rooms
            .iter()
            .flat_map(|r| r.walls.iter().map(move |w| (r, w)))
            .flat_map(|(r, w)| w.openings.iter().map(move |o| (r, w, o)))
            .map(|(r, w, o)| {
                vec![
                    r.id.to_owned(),
                    w.id.to_owned(),
                    o.id.to_owned(),
                    o.kind.to_owned(),
                    format!("{} - {}", num(o.along[0]), num(o.along[1])),
                    format!("{} - {}", num(o.height[0]), num(o.height[1])),
                ]
            })
            .collect();
        table(
            out,
            &["room", "wall", "id", "kind", "along", "height"],
            &[false, false, false, false, false, false],
            rows,
        )
    }
}

/// `1 room`, `2 rooms`.
fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// A number with three decimals (millimetres), without a negative zero.
fn num(v: Real) -> String {
    let s = format!("{v:.3}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_owned()
    } else {
        s
    }
}

/// Writes an aligned table: a header, a rule, and the rows; `right` marks right-aligned
/// (numeric) columns. An empty table prints `(none)`.
fn table(out: &mut impl Write, header: &[&str], right: &[bool], rows: Vec<Vec<String>>) -> io::Result<()> {
    if rows.is_empty() {
        return writeln!(out, "  (none)");
    }
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::from(" ");
        for (i, cell) in cells.iter().enumerate() {
            let pad = widths[i].saturating_sub(cell.chars().count());
            s.push(' ');
            if right.get(i).copied().unwrap_or(false) {
                s.push_str(&" ".repeat(pad));
                s.push_str(cell);
            } else {
                s.push_str(cell);
                s.push_str(&" ".repeat(pad));
            }
            s.push(' ');
        }
        s.trim_end().to_owned()
    };
    let header: Vec<String> = header.iter().map(|h| (*h).to_owned()).collect();
    writeln!(out, "{}", line(&header))?;
    let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
    writeln!(out, "{}", line(&rule))?;
    for row in &rows {
        writeln!(out, "{}", line(row))?;
    }
    Ok(())
}

/// A declared front as an axis name (`+y`, `-x`, ...), or its components.
fn axis_name(v: [Real; 3]) -> String {
    match v {
        [x, y, z] if y == 0.0 && z == 0.0 && x != 0.0 => format!("{}x", if x > 0.0 { '+' } else { '-' }),
        [x, y, z] if x == 0.0 && z == 0.0 && y != 0.0 => format!("{}y", if y > 0.0 { '+' } else { '-' }),
        [x, y, z] => format!("({}, {}, {})", num(x), num(y), num(z)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_three_decimals_and_no_negative_zero() {
        assert_eq!(num(1.23456), "1.235");
        assert_eq!(num(-0.0001), "0.000");
        assert_eq!(num(-2.5), "-2.500");
        assert_eq!(count(1, "room"), "1 room");
        assert_eq!(count(0, "room"), "0 rooms");
        assert_eq!(axis_name([0.0, 1.0, 0.0]), "+y");
        assert_eq!(axis_name([-1.0, 0.0, 0.0]), "-x");
    }

    #[test]
    fn tables_align_columns() {
        let mut out = Vec::new();
        table(
            &mut out,
            &["id", "x"],
            &[false, true],
            vec![
                vec!["a".into(), "1.000".into()],
                vec!["long".into(), "10.000".into()],
            ],
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "  id         x\n  ----  ------\n  a      1.000\n  long  10.000\n"
        );
        let mut out = Vec::new();
        table(&mut out, &["id"], &[false], vec![]).unwrap();
        assert_eq!(String::from_utf8(out).unwrap(), "  (none)\n");
    }
}
