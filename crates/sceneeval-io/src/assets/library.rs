//! The per-run asset cache.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::hash::Hash;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use sceneeval_geom::conventions::object_from_asset;
use sceneeval_geom::{Isometry3, Matrix3, Mesh, Point3, Rotation3, Vector3};
use sceneeval_scene::{ObjectId, SceneObject};

use super::{AssetInfo, AssetLocation, AssetSource, AssetSpec, split_model_id};
use crate::appearance::{Appearance, load_appearance};
use crate::frames::{ObjectFront, PlacedObject};
use crate::mesh_load::read_mesh_file_with;
use crate::{IoError, Limits};

/// A loaded asset: its mesh in the **object frame** (z up, front -y; unscaled) and its
/// metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct Asset {
    /// The model id `PREFIX.ID`.
    pub model_id: String,
    /// The mesh file it was read from.
    pub path: PathBuf,
    /// Category and description from the source's metadata.
    pub info: AssetInfo,
    /// The mesh in the object frame: `object_from_asset() * p` for the file's vertices `p`
    /// (after the source's alignment, if any).
    pub mesh: Arc<Mesh>,
    /// Every file the asset was built from: the mesh file, its external buffers, then the
    /// metadata files the source consulted (some of which may not exist).
    pub files: Vec<PathBuf>,
}

type Slot<V> = Arc<Mutex<Option<V>>>;
type Cache<K, V> = Mutex<HashMap<K, Slot<V>>>;

/// Asset sources by model id prefix, and a cache that loads each asset (and each scaled
/// variant of it) once.
///
/// The library is `Sync`: share one by reference across scenes and threads. Two threads
/// asking for the same asset wait for one load; different assets load in parallel. Failed
/// loads are not cached (asking again retries and fails again with the same error).
///
/// ```
/// use sceneeval_io::{AssetLibrary, GlbMesh, write_glb};
/// use sceneeval_io::assets::PlainFolderSource;
/// use sceneeval_geom::Vector3;
///
/// let dir = tempfile::tempdir().unwrap();
/// // A unit triangle standing in the asset's x-y plane (y up).
/// let tri = GlbMesh::new("t", vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![0, 1, 2]);
/// write_glb(&dir.path().join("tri.glb"), &[tri]).unwrap();
///
/// let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir.path()));
/// let asset = library.asset("fixture.tri").unwrap();
/// // Asset +y (up) is object +z.
/// assert_eq!(asset.mesh.aabb().max.z, 1.0);
/// let a = library.mesh("fixture.tri", &Vector3::repeat(1.0)).unwrap();
/// let b = library.mesh("fixture.tri", &Vector3::repeat(1.0)).unwrap();
/// assert!(std::sync::Arc::ptr_eq(&a, &b), "one mesh per asset");
/// assert_eq!(library.files_read(), 1);
/// ```
#[derive(Default)]
pub struct AssetLibrary {
    sources: BTreeMap<String, Box<dyn AssetSource>>,
    limits: Limits,
    assets: Cache<String, Arc<Asset>>,
    scaled: Cache<(String, [u64; 3], ObjectFront), Arc<Mesh>>,
    files_read: AtomicUsize,
    appearances: Cache<(String, ObjectFront), Arc<Appearance>>,
}

impl fmt::Debug for AssetLibrary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut m = f.debug_map();
        for (prefix, source) in &self.sources {
            m.entry(
                prefix,
                &format_args!("{} {}", source.layout(), source.root().display()),
            );
        }
        m.finish()
    }
}

impl AssetLibrary {
    /// A library with no sources (enough for scenes made only of box objects).
    pub fn new() -> Self {
        AssetLibrary::default()
    }

    /// Replaces the [`Limits`] applied to every scene file and asset read through this
    /// library (default: [`Limits::default`]). Assets already loaded are kept.
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The limits applied to every file and asset read through this library.
    #[inline]
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// Registers `source` for model ids `PREFIX.*`, replacing any source registered for that
    /// prefix.
    pub fn with_source(mut self, prefix: impl Into<String>, source: impl AssetSource + 'static) -> Self {
        self.sources.insert(prefix.into(), Box::new(source));
        self
    }

    /// Registers a boxed source for `prefix`.
    ///
    /// # Errors
    /// [`IoError::BadAssetSpec`] when a source is already registered for the prefix.
    pub fn add_source(
        &mut self,
        prefix: impl Into<String>,
        source: Box<dyn AssetSource>,
    ) -> Result<(), IoError> {
        let prefix = prefix.into();
        if let Some(old) = self.sources.get(&prefix) {
            return Err(IoError::BadAssetSpec {
                spec: format!("{prefix}={}", source.root().display()),
                reason: format!(
                    "prefix {prefix:?} is already registered for {}",
                    old.root().display()
                ),
            });
        }
        self.sources.insert(prefix, source);
        Ok(())
    }

    /// A library from `--assets` specifications (see [`AssetSpec::parse`]).
    ///
    /// # Errors
    /// [`IoError::BadAssetSpec`] when a specification does not parse, its folder is not a
    /// directory, or two name the same prefix.
    pub fn from_specs<S: AsRef<str>>(specs: &[S]) -> Result<Self, IoError> {
        let mut library = AssetLibrary::new();
        for spec in specs {
            let spec_str = spec.as_ref();
            let parsed = AssetSpec::parse(spec_str)?;
            if !parsed.dir.is_dir() {
                return Err(IoError::BadAssetSpec {
                    spec: spec_str.to_owned(),
                    reason: format!("{} is not a directory", parsed.dir.display()),
                });
            }
            library.add_source(parsed.prefix, parsed.layout.source(parsed.dir))?;
        }
        Ok(library)
    }

    /// The source registered for `prefix`.
    pub fn source(&self, prefix: &str) -> Option<&dyn AssetSource> {
        self.sources.get(prefix).map(|s| s.as_ref())
    }

    /// The registered prefixes, sorted.
    pub fn prefixes(&self) -> impl Iterator<Item = &str> + '_ {
        self.sources.keys().map(String::as_str)
    }

    /// How many mesh files have been read so far (each asset is read once).
    pub fn files_read(&self) -> usize {
        self.files_read.load(Ordering::Relaxed)
    }

    /// The asset `model_id` (`PREFIX.ID`), loading it on first use.
    ///
    /// # Errors
    /// [`IoError::BadModelId`], [`IoError::UnknownPrefix`], the source's errors
    /// ([`IoError::AssetNotFound`], [`IoError::BadMetadata`]), the mesh reader's errors
    /// ([`IoError::File`], [`IoError::BadAssetFile`], [`IoError::EmptyMesh`]) and
    /// [`IoError::AssetGeometry`].
    pub fn asset(&self, model_id: &str) -> Result<Arc<Asset>, IoError> {
        let slot = slot(&self.assets, model_id.to_owned());
        cached(&slot, || self.load(model_id).map(Arc::new))
    }

    /// The object-frame mesh of `model_id` scaled by `scale` (object frame: x width, y
    /// depth, z height), shared by every caller asking for the same asset and scale. A scale
    /// of `(1, 1, 1)` returns the asset's own mesh.
    ///
    /// # Errors
    /// As [`AssetLibrary::asset`]; [`IoError::BadScale`] when a scale component is zero or
    /// not finite.
    pub fn mesh(&self, model_id: &str, scale: &Vector3) -> Result<Arc<Mesh>, IoError> {
        self.mesh_facing(model_id, scale, ObjectFront::MinusY)
    }

    /// The object-frame mesh of `model_id` scaled by `scale` and then turned so that
    /// `front`, the front its scene file declares for it (sceneState `objectFrontVector`), is
    /// local -y: `Q * diag(scale) * m` with `Q = front.turn()`. Its object-frame scale is then
    /// `front.turn_scale(scale)`. Shared like [`AssetLibrary::mesh`]; the model's own front
    /// ([`ObjectFront::MinusY`]) is [`AssetLibrary::mesh`] itself.
    ///
    /// # Errors
    /// As [`AssetLibrary::mesh`].
    pub fn mesh_facing(
        &self,
        model_id: &str,
        scale: &Vector3,
        front: ObjectFront,
    ) -> Result<Arc<Mesh>, IoError> {
        check_scale(model_id, scale)?;
        let asset = self.asset(model_id)?;
        if front == ObjectFront::MinusY && *scale == Vector3::repeat(1.0) {
            return Ok(Arc::clone(&asset.mesh));
        }
        let key = (
            model_id.to_owned(),
            [scale.x, scale.y, scale.z].map(f64::to_bits),
            front,
        );
        let slot = slot(&self.scaled, key);
        cached(&slot, || {
            // The identity turn leaves diag(scale) exact.
            let linear = front.turn().matrix() * Matrix3::from_diagonal(scale);
            asset
                .mesh
                .transformed(&linear, &Vector3::zeros())
                .map(Arc::new)
                .map_err(|source| IoError::AssetGeometry {
                    path: asset.path.clone(),
                    source,
                })
        })
    }

    /// The look of asset `model_id` turned as [`AssetLibrary::mesh_facing`] turns its mesh,
    /// for an object whose scene file declares the front `front` (a renderer passes
    /// [`SceneObject::asset_front`]); `None` is [`AssetLibrary::appearance`] itself.
    ///
    /// # Errors
    /// [`IoError::InvalidValue`] (naming the model id) when `front` is not a horizontal axis
    /// direction; otherwise as [`AssetLibrary::appearance`].
    pub fn appearance_facing(
        &self,
        model_id: &str,
        front: Option<&Vector3>,
    ) -> Result<Arc<Appearance>, IoError> {
        let front = match front {
            None => ObjectFront::MinusY,
            Some(v) => ObjectFront::from_vector([v.x, v.y, v.z]).map_err(|reason| IoError::InvalidValue {
                path: PathBuf::from(model_id),
                pointer: "/objectFrontVector".into(),
                reason,
            })?,
        };
        self.look(model_id, front)
    }

    /// The look of `model_id` turned to `front`, loaded once.
    fn look(&self, model_id: &str, front: ObjectFront) -> Result<Arc<Appearance>, IoError> {
        let slot = slot(&self.appearances, (model_id.to_owned(), front));
        cached(&slot, || {
            let location = self.locate(model_id)?;
            let alignment = match front {
                ObjectFront::MinusY => location.alignment,
                // object_from_file(A') = Rx(90) * A' must be Q * Rx(90) * A.
                _ => {
                    let rx = object_from_asset();
                    let file = location.alignment.unwrap_or_else(Rotation3::identity);
                    Some(rx.inverse() * front.turn() * rx * file)
                }
            };
            load_appearance(model_id, &location.path, alignment.as_ref(), &self.limits).map(Arc::new)
        })
    }

    /// A scene object showing asset `model_id` at `pose` with the object-frame `scale`, with
    /// the asset's category and description. This is how code that builds scenes places
    /// assets: the frame conversion stays in this crate.
    ///
    /// # Errors
    /// As [`AssetLibrary::mesh`]; [`IoError::BadObject`] when the pose is not finite.
    pub fn object(
        &self,
        id: impl Into<ObjectId>,
        model_id: &str,
        pose: Isometry3,
        scale: Vector3,
    ) -> Result<SceneObject, IoError> {
        self.object_facing(id, model_id, &PlacedObject { pose, scale }, ObjectFront::MinusY)
    }

    /// A scene object showing asset `model_id` placed as a scene file places it: `placed` is
    /// the pose and object-frame scale in the file's own frame (see
    /// [`crate::frames::TransformFrame::placed`]), `front` the front the file declares for it
    /// (sceneState `objectFrontVector`). The object is turned so that local -y is its front
    /// ([`ObjectFront::model_pose`], [`AssetLibrary::mesh_facing`]) and records the declared
    /// front ([`SceneObject::asset_front`]): the object `read_scene_state` builds for such an
    /// entry, which is how converters place a generator's objects.
    ///
    /// # Errors
    /// As [`AssetLibrary::object`].
    pub fn object_facing(
        &self,
        id: impl Into<ObjectId>,
        model_id: &str,
        placed: &PlacedObject,
        front: ObjectFront,
    ) -> Result<SceneObject, IoError> {
        let id = id.into();
        let asset = self.asset(model_id)?;
        let mesh = self.mesh_facing(model_id, &placed.scale, front)?;
        let mut object = SceneObject::from_mesh(id.clone(), mesh, front.model_pose(&placed.pose))
            .map_err(|source| IoError::BadObject {
                object: id.to_string(),
                source,
            })?
            .with_model_id(model_id)
            .with_scale(front.turn_scale(&placed.scale));
        if front != ObjectFront::MinusY {
            object = object.with_asset_front(front.vector());
        }
        if let Some(c) = &asset.info.category {
            object = object.with_category(c.clone());
        }
        if let Some(d) = &asset.info.description {
            object = object.with_description(d.clone());
        }
        Ok(object)
    }

    /// The look of asset `model_id` (materials, textures and a render mesh in the object
    /// frame), loaded on first use and shared by every caller. Only renderers need this;
    /// reading scenes never calls it, so geometry-only runs decode no texture. See
    /// [`crate::appearance`].
    ///
    /// # Errors
    /// As [`AssetLibrary::asset`] for locating and parsing the file. Missing or broken
    /// textures and material libraries are logged and fall back to the base colour.
    pub fn appearance(&self, model_id: &str) -> Result<Arc<Appearance>, IoError> {
        self.look(model_id, ObjectFront::MinusY)
    }

    /// How many appearances have been loaded so far (0 in a run that never rendered).
    pub fn appearances_loaded(&self) -> usize {
        let map = self.appearances.lock().unwrap_or_else(PoisonError::into_inner);
        map.values()
            .filter(|slot| slot.lock().unwrap_or_else(PoisonError::into_inner).is_some())
            .count()
    }

    /// Where the asset `model_id` is (mesh file, metadata files, category), without loading
    /// its mesh: what a result cache needs to tell whether an asset changed.
    ///
    /// # Errors
    /// [`IoError::BadModelId`], [`IoError::UnknownPrefix`] and the source's errors.
    pub fn locate(&self, model_id: &str) -> Result<AssetLocation, IoError> {
        let (prefix, asset_id) = split_model_id(model_id)?;
        let Some(source) = self.sources.get(prefix) else {
            return Err(IoError::UnknownPrefix {
                model_id: model_id.to_owned(),
                prefix: prefix.to_owned(),
                registered: self.sources.keys().cloned().collect(),
            });
        };
        source.locate(model_id, asset_id)
    }

    /// The asset `model_id` if it has been loaded already; never loads it.
    pub fn loaded(&self, model_id: &str) -> Option<Arc<Asset>> {
        let map = self.assets.lock().unwrap_or_else(PoisonError::into_inner);
        let slot = Arc::clone(map.get(model_id)?);
        drop(map);
        let guard = slot.lock().unwrap_or_else(PoisonError::into_inner);
        guard.clone()
    }

    fn load(&self, model_id: &str) -> Result<Asset, IoError> {
        let location = self.locate(model_id)?;
        let raw = read_mesh_file_with(&location.path, &self.limits)?;
        self.files_read.fetch_add(1, Ordering::Relaxed);
        let to_object = crate::frames::object_from_file(location.alignment.as_ref());
        let vertices = raw
            .positions
            .iter()
            .map(|p| Point3::from(to_object * p.coords))
            .collect();
        let mesh = Mesh::new(vertices, raw.triangles).map_err(|source| IoError::AssetGeometry {
            path: location.path.clone(),
            source,
        })?;
        tracing::debug!(model_id, file = %location.path.display(), "asset loaded");
        let mut files = raw.files;
        files.extend(location.metadata);
        Ok(Asset {
            model_id: model_id.to_owned(),
            path: location.path,
            info: location.info,
            mesh: Arc::new(mesh),
            files,
        })
    }
}

fn check_scale(model_id: &str, scale: &Vector3) -> Result<(), IoError> {
    if scale.iter().all(|s| s.is_finite() && *s != 0.0) {
        Ok(())
    } else {
        Err(IoError::BadScale {
            model_id: model_id.to_owned(),
            scale: [scale.x, scale.y, scale.z],
        })
    }
}

fn slot<K: Eq + Hash, V>(cache: &Cache<K, V>, key: K) -> Slot<V> {
    let mut map = cache.lock().unwrap_or_else(PoisonError::into_inner);
    Arc::clone(map.entry(key).or_default())
}

fn cached<V: Clone>(slot: &Slot<V>, load: impl FnOnce() -> Result<V, IoError>) -> Result<V, IoError> {
    let mut guard = slot.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(v) = guard.as_ref() {
        return Ok(v.clone());
    }
    let v = load()?;
    *guard = Some(v.clone());
    Ok(v)
}
