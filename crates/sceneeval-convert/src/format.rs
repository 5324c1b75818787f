//! The generators [`crate::convert`] reads, and the format table: one row per format with what
//! sets it apart (its name, the model id prefix of its objects, whether it needs an asset
//! folder, the assets it writes into the output) and its [`Converter`]. Everything that
//! differs between formats is in this table or in the format's own module; [`crate::convert`]
//! is the same for every format.

use std::path::Path;
use std::str::FromStr;

use sceneeval_io::AssetLibrary;
use sceneeval_io::assets::Layout;

use crate::output::Output;
use crate::{ConvertError, NativeScene, Written, holodeck, idesign, layoutvlm, scene_agent};

/// A generator whose output [`crate::convert`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// Holodeck (AI2-THOR house JSON, Unity's y-up left-handed frame).
    Holodeck,
    /// LayoutVLM (`scene.json` with the room and the assets, `layout.json` with placements).
    #[serde(rename = "layoutvlm")]
    LayoutVlm,
    /// IDesign (`scene_graph.json` and the retrieved GLB files).
    #[serde(rename = "idesign")]
    IDesign,
    /// SceneAgent / SceneSmith (its own sceneState export, SDF + glTF assets per room).
    SceneAgent,
}

/// One format's conversion: how its batch folder is split into scenes, and how one scene is
/// converted. Each format implements it once, in its own module.
pub(crate) trait Converter: Sync {
    /// The scenes of the batch folder `input`, in key order. By default its `scene_NNN`
    /// folders keyed by `NNN`.
    fn scenes(&self, input: &Path) -> Result<Vec<NativeScene>, ConvertError> {
        crate::numbered_scenes(input)
    }

    /// What the batch folder must hold, for the error when it holds no scene.
    fn expected_scenes(&self) -> &'static str {
        "scene_NNN folders"
    }

    /// Converts `scene` into `scene_<id>.json` of `out` (and the assets that travel with it),
    /// loading assets through `library`.
    fn convert(
        &self,
        scene: &NativeScene,
        id: u64,
        out: Output<'_>,
        library: &AssetLibrary,
    ) -> Result<Written, ConvertError>;
}

/// A row of the format table.
struct Row {
    format: Format,
    /// The name used on the command line.
    name: &'static str,
    /// The model id prefix of the converted scenes' objects.
    asset_prefix: &'static str,
    /// Whether the format places objects by their box centres, which only the meshes of the
    /// `asset_prefix` folder tell.
    box_centres: bool,
    /// The prefixes whose assets the conversion writes into the output, with their layouts.
    in_output: &'static [(&'static str, Layout)],
    converter: &'static dyn Converter,
}

/// The format table, in [`Format::ALL`] order.
const TABLE: [Row; 4] = [
    Row {
        format: Format::Holodeck,
        name: "holodeck",
        asset_prefix: "objaverse",
        box_centres: true,
        in_output: &[],
        converter: &holodeck::Holodeck,
    },
    Row {
        format: Format::LayoutVlm,
        name: "layoutvlm",
        asset_prefix: "layoutvlm-objaverse",
        box_centres: true,
        in_output: &[],
        converter: &layoutvlm::LayoutVlm,
    },
    Row {
        format: Format::IDesign,
        name: "idesign",
        asset_prefix: "idesign",
        box_centres: false,
        in_output: &[("idesign", Layout::IDesign)],
        converter: &idesign::IDesign,
    },
    Row {
        format: Format::SceneAgent,
        name: "scene-agent",
        asset_prefix: "scene-agent",
        box_centres: false,
        in_output: &[
            ("scene-agent", Layout::SceneAgent),
            ("scenesmith", Layout::SceneAgent),
        ],
        converter: &scene_agent::SceneAgent,
    },
];

// Each row sits at its format's position.
const _: () = {
    let mut i = 0;
    while i < TABLE.len() {
        assert!(TABLE[i].format as usize == i);
        i += 1;
    }
};

impl Format {
    /// Every format.
    pub const ALL: [Format; 4] = [
        Format::Holodeck,
        Format::LayoutVlm,
        Format::IDesign,
        Format::SceneAgent,
    ];

    const fn row(self) -> &'static Row {
        &TABLE[self as usize]
    }

    /// The name used on the command line: `holodeck`, `layoutvlm`, `idesign`, `scene-agent`.
    pub const fn name(self) -> &'static str {
        self.row().name
    }

    /// The model id prefix of the converted scenes' objects.
    pub const fn asset_prefix(self) -> &'static str {
        self.row().asset_prefix
    }

    /// The prefix whose asset folder the conversion needs ([`Format::asset_prefix`], for the
    /// formats that place objects by their box centres: Holodeck, LayoutVLM); `None` when the
    /// assets come with the scenes.
    pub const fn needs_assets(self) -> Option<&'static str> {
        match self.row().box_centres {
            true => Some(self.row().asset_prefix),
            false => None,
        }
    }

    /// The prefix whose assets the conversion writes into the output folder (IDesign's
    /// `idesign`, SceneAgent's `scene-agent`): the converted scenes are read with that prefix's
    /// folder being the output folder. `None` for the formats whose assets stay where they are.
    pub const fn assets_in_output(self) -> Option<&'static str> {
        match self.row().in_output.first() {
            Some((prefix, _)) => Some(*prefix),
            None => None,
        }
    }

    /// The prefixes (with their layouts) served from the output folder itself.
    pub(crate) const fn output_sources(self) -> &'static [(&'static str, Layout)] {
        self.row().in_output
    }

    /// The format's conversion.
    pub(crate) fn converter(self) -> &'static dyn Converter {
        self.row().converter
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Format {
    type Err = String;

    /// Parses a format name (`scenesmith` is `scene-agent`), ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("scenesmith") {
            return Ok(Format::SceneAgent);
        }
        Format::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown format {s:?} (expected one of {})",
                    Format::ALL.map(Format::name).join(", ")
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_names_round_trip() {
        for (f, layout, needs, in_output) in [
            (Format::Holodeck, "objathor", Some("objaverse"), None),
            (Format::LayoutVlm, "layoutvlm", Some("layoutvlm-objaverse"), None),
            (Format::IDesign, "idesign", None, Some("idesign")),
            (Format::SceneAgent, "scene-agent", None, Some("scene-agent")),
        ] {
            assert_eq!(f.name().parse::<Format>().unwrap(), f);
            assert_eq!(Layout::for_prefix(f.asset_prefix()).name(), layout);
            assert_eq!((f.needs_assets(), f.assets_in_output()), (needs, in_output));
            // The assets written into the output are those of the objects' own prefix.
            for (prefix, l) in f.output_sources() {
                assert_eq!(Layout::for_prefix(prefix), *l);
            }
        }
        assert_eq!("SceneSmith".parse::<Format>().unwrap(), Format::SceneAgent);
        assert!("sceneweaver".parse::<Format>().is_err());
    }
}
