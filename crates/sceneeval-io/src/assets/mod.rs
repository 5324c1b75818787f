//! Asset sources and the per-run asset cache.
//!
//! A model id `PREFIX.ID` (split on the **first** dot) resolves through the [`AssetSource`]
//! registered for `PREFIX` in an [`AssetLibrary`]. Seven directory layouts are provided (see
//! [`Layout`] and `docs/formats.md`, "Asset folders"):
//!
//! | layout | default prefix | mesh | metadata |
//! |---|---|---|---|
//! | [`Layout::ThreeDFuture`] | `3dfModel` | `ID/raw_model.obj` | `model_info.json` |
//! | [`Layout::Objathor`] | `objaverse` | `ID/ID.glb` | `annotations.json` |
//! | [`Layout::Hssd`] | `fpModel` | `glb/<first char>/ID.glb` (`decomposed/<base>/ID.glb` for parts) | `fpmodels.csv` |
//! | [`Layout::LayoutVlm`] | `layoutvlm-objaverse` | `ID/ID.glb` | `ID/data.json` |
//! | [`Layout::IDesign`] | `idesign` | `scene_<S>/assets/<O>.glb` for ID `scene_<S>__<O>` | `scene_<S>.json` |
//! | [`Layout::SceneAgent`] | `scene-agent`, `scenesmith` | the glTF of the SDF named by the `sdfPath` of object `<O>` in `scene_<S>.json` | `scene_<S>.json` |
//! | [`Layout::Plain`] | any other | `ID.glb`, `ID.gltf` or `ID.obj` | optional `ID.json` |
//!
//! The [`AssetLibrary`] loads each asset once per run and hands out `Arc<Mesh>`es, so every
//! object of one asset (at one scale) shares one mesh and one BVH. It is `Sync`: share one
//! library by reference across scenes and threads.

/// Declares an asset source that reads a folder: the struct (the folder and the given
/// fields, with their initial values), its `new(root)`, and its [`AssetSource`] impl (`locate`
/// is the struct's own `find`, `layout` the given [`Layout`], `root` the folder). Each layout
/// then writes only what is its own: where its meshes and metadata are.
macro_rules! folder_source {
    ($(#[$doc:meta])* $name:ident, $layout:expr, { $($field:ident: $ty:ty = $init:expr)? }) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $name {
            root: PathBuf,
            $($field: $ty,)?
        }

        impl $name {
            /// A source rooted at `root`.
            pub fn new(root: impl Into<PathBuf>) -> Self {
                $name {
                    root: root.into(),
                    $($field: $init,)?
                }
            }
        }

        impl AssetSource for $name {
            fn locate(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
                self.find(model_id, asset_id)
            }

            fn layout(&self) -> Layout {
                $layout
            }

            fn root(&self) -> &Path {
                &self.root
            }
        }
    };
}

mod generated;
mod library;
mod sources;

pub use generated::{IDesignSource, SceneAgentSource, humanize_object_id, split_scene_asset_id};
pub use library::{Asset, AssetLibrary};
pub use sources::{HssdSource, LayoutVlmSource, ObjathorSource, PlainFolderSource, ThreeDFutureSource};

use std::path::{Path, PathBuf};
use std::str::FromStr;

use sceneeval_geom::Rotation3;

use crate::IoError;

/// What an asset's metadata says about it.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct AssetInfo {
    /// The asset's category (e.g. `nightstand`), if known.
    pub category: Option<String>,
    /// A free-text description, if known (for the dataset layouts, the string the reference
    /// implementation sends to its VLM).
    pub description: Option<String>,
}

/// Where an asset's mesh file is and what is known about it.
#[derive(Debug, Clone, PartialEq)]
pub struct AssetLocation {
    /// The mesh file (`.glb`, `.gltf` or `.obj`).
    pub path: PathBuf,
    /// Category and description from the metadata.
    pub info: AssetInfo,
    /// A rotation applied to the file's coordinates before the standard y-up, front-+z
    /// conversion, for datasets whose assets are not stored in that convention (HSSD rows with
    /// `up` and `front`).
    pub alignment: Option<Rotation3>,
    /// The metadata files consulted for `info` and `alignment`, whether or not they exist
    /// (a metadata file appearing later changes the asset's category).
    pub metadata: Vec<PathBuf>,
}

/// A place assets come from: maps an asset id (the part of a model id after the prefix) to
/// its mesh file and metadata.
pub trait AssetSource: Send + Sync + std::fmt::Debug {
    /// Locates asset `asset_id`; `model_id` is the full `PREFIX.ID`, for error messages.
    ///
    /// # Errors
    /// [`IoError::AssetNotFound`] when there is no mesh file for the id,
    /// [`IoError::BadMetadata`] when the metadata file is malformed.
    fn locate(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError>;

    /// The directory layout this source reads.
    fn layout(&self) -> Layout;

    /// The source's root directory.
    fn root(&self) -> &Path;
}

/// The supported asset folder layouts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Layout {
    /// 3D-FUTURE: `ID/raw_model.obj`, metadata `model_info.json`.
    #[serde(rename = "3d-future")]
    ThreeDFuture,
    /// Objathor (Holodeck): `ID/ID.glb`, metadata `annotations.json`.
    Objathor,
    /// HSSD: `glb/<first char>/ID.glb`, metadata `fpmodels.csv`.
    Hssd,
    /// LayoutVLM's Objathor subset: `ID/ID.glb`, metadata `ID/data.json`.
    #[serde(rename = "layoutvlm")]
    LayoutVlm,
    /// IDesign scenes converted by `sceneeval convert idesign` (or the SceneSmith fork):
    /// `scene_<S>/assets/<O>.glb` for asset id `scene_<S>__<O>` ([`IDesignSource`]).
    #[serde(rename = "idesign")]
    IDesign,
    /// SceneAgent / SceneSmith scenes converted by `sceneeval convert scene-agent` (or the
    /// SceneSmith fork): the glTF of each object's SDF ([`SceneAgentSource`]).
    SceneAgent,
    /// A plain folder: `ID.glb`, `ID.gltf` or `ID.obj`, optional sidecar `ID.json`.
    Plain,
}

impl Layout {
    /// Every layout.
    pub const ALL: [Layout; 7] = [
        Layout::ThreeDFuture,
        Layout::Objathor,
        Layout::Hssd,
        Layout::LayoutVlm,
        Layout::IDesign,
        Layout::SceneAgent,
        Layout::Plain,
    ];

    /// The name used in `--assets PREFIX=LAYOUT:DIR`.
    pub const fn name(self) -> &'static str {
        match self {
            Layout::ThreeDFuture => "3d-future",
            Layout::Objathor => "objathor",
            Layout::Hssd => "hssd",
            Layout::LayoutVlm => "layoutvlm",
            Layout::IDesign => "idesign",
            Layout::SceneAgent => "scene-agent",
            Layout::Plain => "plain",
        }
    }

    /// The layout the reference (or its SceneSmith fork) uses for a model id prefix:
    /// `3dfModel` 3D-FUTURE, `objaverse` Objathor, `fpModel` HSSD, `layoutvlm-objaverse`
    /// LayoutVLM, `idesign` IDesign, `scene-agent` and `scenesmith` SceneAgent (the fork
    /// registers no source for `scenesmith`, SceneSmith's own prefix), anything else the
    /// plain folder.
    pub fn for_prefix(prefix: &str) -> Layout {
        match prefix {
            "3dfModel" => Layout::ThreeDFuture,
            "objaverse" => Layout::Objathor,
            "fpModel" => Layout::Hssd,
            "layoutvlm-objaverse" => Layout::LayoutVlm,
            "idesign" => Layout::IDesign,
            "scene-agent" | "scenesmith" => Layout::SceneAgent,
            _ => Layout::Plain,
        }
    }

    /// A source of this layout rooted at `dir`.
    pub fn source(self, dir: impl Into<PathBuf>) -> Box<dyn AssetSource> {
        let dir = dir.into();
        match self {
            Layout::ThreeDFuture => Box::new(ThreeDFutureSource::new(dir)),
            Layout::Objathor => Box::new(ObjathorSource::new(dir)),
            Layout::Hssd => Box::new(HssdSource::new(dir)),
            Layout::LayoutVlm => Box::new(LayoutVlmSource::new(dir)),
            Layout::IDesign => Box::new(IDesignSource::new(dir)),
            Layout::SceneAgent => Box::new(SceneAgentSource::new(dir)),
            Layout::Plain => Box::new(PlainFolderSource::new(dir)),
        }
    }
}

impl std::fmt::Display for Layout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Layout {
    type Err = String;

    /// Parses a layout name (`3d-future`, `objathor`, `hssd`, `layoutvlm`, `idesign`,
    /// `scene-agent`, `plain`), ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Layout::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                format!(
                    "unknown layout {s:?} (expected one of {})",
                    Layout::ALL.map(Layout::name).join(", ")
                )
            })
    }
}

/// A parsed `--assets` argument: `PREFIX=DIR` (layout chosen by the prefix, see
/// [`Layout::for_prefix`]) or `PREFIX=LAYOUT:DIR`.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct AssetSpec {
    /// The model id prefix.
    pub prefix: String,
    /// The folder layout.
    pub layout: Layout,
    /// The folder.
    pub dir: PathBuf,
}

impl AssetSpec {
    /// Parses `PREFIX=DIR` or `PREFIX=LAYOUT:DIR`. A `LAYOUT:` part is recognised only when
    /// it names a layout, so `fixture=C:/assets` is a plain folder `C:/assets`. The folder is
    /// not checked here (see [`AssetLibrary::from_specs`]).
    ///
    /// ```
    /// use sceneeval_io::assets::{AssetSpec, Layout};
    /// let s = AssetSpec::parse("3dfModel=/data/3D-FUTURE-model").unwrap();
    /// assert_eq!(s.layout, Layout::ThreeDFuture);
    /// let s = AssetSpec::parse("fixture=objathor:/data/objathor").unwrap();
    /// assert_eq!((s.prefix.as_str(), s.layout), ("fixture", Layout::Objathor));
    /// assert_eq!(s.dir, std::path::PathBuf::from("/data/objathor"));
    /// assert!(AssetSpec::parse("no-equals-sign").is_err());
    /// ```
    ///
    /// # Errors
    /// [`IoError::BadAssetSpec`] when there is no `=`, the prefix is empty or contains a dot,
    /// or the folder is empty.
    pub fn parse(spec: &str) -> Result<AssetSpec, IoError> {
        let bad = |reason: &str| IoError::BadAssetSpec {
            spec: spec.to_owned(),
            reason: reason.to_owned(),
        };
        let Some((prefix, rest)) = spec.split_once('=') else {
            return Err(bad("expected PREFIX=DIR or PREFIX=LAYOUT:DIR"));
        };
        let prefix = prefix.trim();
        if prefix.is_empty() {
            return Err(bad("the prefix is empty"));
        }
        if prefix.contains('.') {
            return Err(bad(
                "the prefix must not contain a dot (model ids split on the first dot)",
            ));
        }
        let (layout, dir) = match rest.split_once(':') {
            Some((name, dir)) => match name.parse::<Layout>() {
                Ok(layout) => (layout, dir),
                Err(_) => (Layout::for_prefix(prefix), rest),
            },
            None => (Layout::for_prefix(prefix), rest),
        };
        if dir.is_empty() {
            return Err(bad("the folder is empty"));
        }
        Ok(AssetSpec {
            prefix: prefix.to_owned(),
            layout,
            dir: PathBuf::from(dir),
        })
    }
}

impl FromStr for AssetSpec {
    type Err = IoError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        AssetSpec::parse(s)
    }
}

/// Splits a model id `PREFIX.ID` on its first dot.
///
/// ```
/// assert_eq!(sceneeval_io::assets::split_model_id("fpModel.a.b").unwrap(), ("fpModel", "a.b"));
/// assert!(sceneeval_io::assets::split_model_id("nodot").is_err());
/// ```
///
/// # Errors
/// [`IoError::BadModelId`] when there is no dot, either part is empty, or the id could
/// escape the asset folder (contains `/`, `\` or is `..`).
pub fn split_model_id(model_id: &str) -> Result<(&str, &str), IoError> {
    let bad = || IoError::BadModelId {
        model_id: model_id.to_owned(),
    };
    let (prefix, id) = model_id.split_once('.').ok_or_else(bad)?;
    if prefix.is_empty() || id.is_empty() || id.contains(['/', '\\']) || id == "." || id == ".." {
        return Err(bad());
    }
    Ok((prefix, id))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_pick_layouts_by_prefix_or_name() {
        for (spec, prefix, layout, dir) in [
            ("3dfModel=/d", "3dfModel", Layout::ThreeDFuture, "/d"),
            ("objaverse=/d", "objaverse", Layout::Objathor, "/d"),
            ("fpModel=/d", "fpModel", Layout::Hssd, "/d"),
            (
                "layoutvlm-objaverse=/d",
                "layoutvlm-objaverse",
                Layout::LayoutVlm,
                "/d",
            ),
            (
                "fixture=fixtures/assets",
                "fixture",
                Layout::Plain,
                "fixtures/assets",
            ),
            ("x=hssd:/d", "x", Layout::Hssd, "/d"),
            ("x=3D-FUTURE:/d", "x", Layout::ThreeDFuture, "/d"),
            ("objaverse=plain:/d", "objaverse", Layout::Plain, "/d"),
            ("x=C:/assets", "x", Layout::Plain, "C:/assets"),
            ("idesign=/d", "idesign", Layout::IDesign, "/d"),
            ("scene-agent=/d", "scene-agent", Layout::SceneAgent, "/d"),
            ("scenesmith=/d", "scenesmith", Layout::SceneAgent, "/d"),
            ("x=scene-agent:/d", "x", Layout::SceneAgent, "/d"),
        ] {
            let s = AssetSpec::parse(spec).unwrap();
            assert_eq!(s.prefix, prefix, "{spec}");
            assert_eq!(s.layout, layout, "{spec}");
            assert_eq!(s.dir, PathBuf::from(dir), "{spec}");
        }
        for bad in ["x", "=dir", "a.b=dir", "x=", "x=plain:"] {
            assert!(
                matches!(AssetSpec::parse(bad), Err(IoError::BadAssetSpec { .. })),
                "{bad}"
            );
        }
    }

    #[test]
    fn model_ids_split_on_the_first_dot() {
        assert_eq!(split_model_id("3dfModel.abc").unwrap(), ("3dfModel", "abc"));
        assert_eq!(split_model_id("fpModel.x.y").unwrap(), ("fpModel", "x.y"));
        for bad in ["abc", ".abc", "abc.", "p.../x", "p.a/b", "p..."] {
            let r = split_model_id(bad);
            if bad == "p..." {
                // Id ".." after the first dot.
                assert!(r.is_err());
            } else {
                assert!(matches!(r, Err(IoError::BadModelId { .. })), "{bad}");
            }
        }
    }

    #[test]
    fn layout_names_round_trip() {
        for l in Layout::ALL {
            assert_eq!(l.name().parse::<Layout>().unwrap(), l);
            assert_eq!(l.source("/x").layout(), l);
        }
        assert!("nope".parse::<Layout>().is_err());
    }
}
