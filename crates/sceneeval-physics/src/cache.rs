//! The decomposition cache: each distinct mesh is decomposed once per run (in memory) and once
//! per folder (on disk), so re-runs and the other weld variants reuse it.
//!
//! The key is a blake3 hash of the decomposition parameters and the mesh exactly as the object
//! holds it (vertices and triangles, scale baked in): the same asset at the same scale shares
//! one entry whatever its id or scene, and a changed asset or parameter gets a new one. A file
//! `<key>.bin` holds the pieces' hull vertices as little-endian `f64` (so a piece read back is
//! bit for bit the piece computed), framed by a magic line, the key, counts and a blake3
//! checksum; it is written through [`sceneeval_files::write_atomic`] (a unique temporary name
//! renamed into place, with the mode the umask gives new files) and read only when it is a
//! regular file ([`sceneeval_files::open_regular`]). A file that does not read back (truncated,
//! corrupt, another format version, not a regular file) is decomposed again and overwritten,
//! with a warning.

use std::collections::HashMap;
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use sceneeval_geom::{Mesh, Point3, Vector3};

use crate::decompose::{Decomposition, DecompositionKind, Piece};
use crate::{DecompositionParams, PhysicsError};

/// Format version of the cache files; part of the key, so a new format never reads an old file.
const FORMAT: &[u8; 8] = b"SEPHYS01";
/// Most pieces and points a cache file may declare (bounds the allocation of a corrupt file).
const MAX_FILE_PIECES: usize = 4096;
const MAX_FILE_POINTS: usize = 1 << 20;
/// Largest cache file read (bytes).
const MAX_FILE_BYTES: u64 = 256 << 20;

/// A content hash identifying one mesh under one set of decomposition parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshKey([u8; 32]);

impl MeshKey {
    /// The key of `mesh` decomposed with `params`.
    pub fn new(mesh: &Mesh, params: &DecompositionParams) -> Self {
        let mut h = blake3::Hasher::new();
        h.update(FORMAT);
        h.update(&params.resolution.to_le_bytes());
        h.update(&params.concavity.to_le_bytes());
        h.update(&params.max_pieces.to_le_bytes());
        h.update(&(mesh.vertices().len() as u64).to_le_bytes());
        for v in mesh.vertices() {
            for c in v.iter() {
                h.update(&c.to_le_bytes());
            }
        }
        h.update(&(mesh.triangles().len() as u64).to_le_bytes());
        for t in mesh.triangles() {
            for i in t {
                h.update(&i.to_le_bytes());
            }
        }
        MeshKey(*h.finalize().as_bytes())
    }

    /// The key in lower-case hexadecimal (the cache file's stem).
    pub fn to_hex(&self) -> String {
        self.0.iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// How often the cache answered from memory or disk, and how many meshes it decomposed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CacheStats {
    /// Answers from memory.
    pub memory_hits: usize,
    /// Answers read from disk.
    pub disk_hits: usize,
    /// Meshes decomposed.
    pub decomposed: usize,
}

/// Decompositions by mesh and parameters, shared by every scene and weld variant of a run
/// (share it between threads by reference; it locks internally).
///
/// ```
/// use sceneeval_geom::{Mesh, Vector3};
/// use sceneeval_physics::{DecompositionCache, DecompositionParams};
///
/// let dir = tempfile::tempdir().unwrap();
/// let mesh = Mesh::cuboid(&Vector3::new(0.5, 0.2, 0.1)).unwrap();
/// let first = DecompositionCache::on_disk(dir.path()).unwrap();
/// let a = first.get(&mesh, &DecompositionParams::default());
/// assert_eq!(first.stats().decomposed, 1);
/// // A second run (a new cache on the same folder) reads the file back, bit for bit.
/// let second = DecompositionCache::on_disk(dir.path()).unwrap();
/// let b = second.get(&mesh, &DecompositionParams::default());
/// assert_eq!((second.stats().disk_hits, second.stats().decomposed), (1, 0));
/// assert_eq!(a, b);
/// ```
#[derive(Debug, Default)]
pub struct DecompositionCache {
    dir: Option<PathBuf>,
    memory: Mutex<HashMap<MeshKey, Arc<Decomposition>>>,
    memory_hits: AtomicUsize,
    disk_hits: AtomicUsize,
    decomposed: AtomicUsize,
}

impl DecompositionCache {
    /// A cache that lives only as long as this value.
    pub fn in_memory() -> Self {
        DecompositionCache::default()
    }

    /// A cache backed by files in `dir` (created if missing), e.g. `OUT/physics-cache`.
    ///
    /// # Errors
    /// [`PhysicsError::Cache`] when the folder cannot be created.
    pub fn on_disk(dir: impl Into<PathBuf>) -> Result<Self, PhysicsError> {
        let dir = dir.into();
        fs::create_dir_all(&dir).map_err(|source| PhysicsError::Cache {
            path: dir.clone(),
            source,
        })?;
        Ok(DecompositionCache {
            dir: Some(dir),
            ..DecompositionCache::default()
        })
    }

    /// The cache's folder, if it has one.
    pub fn dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    /// Counts of hits and decompositions so far.
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            memory_hits: self.memory_hits.load(Ordering::Relaxed),
            disk_hits: self.disk_hits.load(Ordering::Relaxed),
            decomposed: self.decomposed.load(Ordering::Relaxed),
        }
    }

    /// The decomposition of `mesh` with `params`: from memory, else from disk, else computed
    /// (and stored in both). Never fails: a cache file that cannot be read or written is
    /// logged and bypassed.
    pub fn get(&self, mesh: &Mesh, params: &DecompositionParams) -> Arc<Decomposition> {
        let key = MeshKey::new(mesh, params);
        if let Some(d) = self.lock().get(&key) {
            self.memory_hits.fetch_add(1, Ordering::Relaxed);
            return d.clone();
        }
        let decomposition = match self.read(&key) {
            Some(d) => {
                self.disk_hits.fetch_add(1, Ordering::Relaxed);
                d
            }
            None => {
                let d = Decomposition::of_mesh(mesh, params);
                self.decomposed.fetch_add(1, Ordering::Relaxed);
                self.write(&key, &d);
                d
            }
        };
        // Two threads may have computed the same key; both results are identical, keep the first.
        self.lock()
            .entry(key)
            .or_insert_with(|| Arc::new(decomposition))
            .clone()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<MeshKey, Arc<Decomposition>>> {
        // A panic while holding the lock cannot leave the map half-updated (inserts are
        // atomic), so a poisoned lock is still usable.
        self.memory.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn path(&self, key: &MeshKey) -> Option<PathBuf> {
        self.dir.as_ref().map(|d| d.join(format!("{}.bin", key.to_hex())))
    }

    fn read(&self, key: &MeshKey) -> Option<Decomposition> {
        let path = self.path(key)?;
        let unreadable = |e: &dyn std::fmt::Display| {
            tracing::warn!(path = %path.display(), error = %e, "decomposition cache file unreadable; decomposing again");
        };
        let file = match sceneeval_files::open_regular(&path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
            Err(e) => {
                unreadable(&e);
                return None;
            }
        };
        // At most one byte more than the largest file read, to tell a too large file.
        let mut bytes = Vec::new();
        if let Err(e) = file.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes) {
            unreadable(&e);
            return None;
        }
        if bytes.len() as u64 > MAX_FILE_BYTES {
            tracing::warn!(path = %path.display(), "decomposition cache file too large; decomposing again");
            return None;
        }
        match decode(&bytes, key) {
            Some(d) => Some(d),
            None => {
                tracing::warn!(path = %path.display(), "decomposition cache file is corrupt; decomposing again");
                None
            }
        }
    }

    fn write(&self, key: &MeshKey, d: &Decomposition) {
        let Some(path) = self.path(key) else { return };
        if let Err(e) = sceneeval_files::write_atomic(&path, &encode(d, key)) {
            tracing::warn!(path = %path.display(), error = %e, "decomposition cache file not written");
        }
    }
}

fn encode(d: &Decomposition, key: &MeshKey) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(FORMAT);
    out.extend_from_slice(&key.0);
    out.push(d.kind().code());
    out.extend_from_slice(&(d.pieces().len() as u32).to_le_bytes());
    let f = |out: &mut Vec<u8>, v: f64| out.extend_from_slice(&v.to_le_bytes());
    for p in d.pieces() {
        match p {
            Piece::Cuboid { center, half_extents } => {
                out.push(0);
                for v in center.iter().chain(half_extents.iter()) {
                    f(&mut out, *v);
                }
            }
            Piece::Hull { points } => {
                out.push(1);
                out.extend_from_slice(&(points.len() as u32).to_le_bytes());
                for p in points {
                    for v in p.iter() {
                        f(&mut out, *v);
                    }
                }
            }
        }
    }
    let checksum = blake3::hash(&out);
    out.extend_from_slice(checksum.as_bytes());
    out
}

/// A byte reader that fails (returns `None`) instead of reading past the end.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        if self.0.len() < n {
            return None;
        }
        let (head, tail) = self.0.split_at(n);
        self.0 = tail;
        Some(head)
    }
    fn u8(&mut self) -> Option<u8> {
        self.take(1).map(|b| b[0])
    }
    fn u32(&mut self) -> Option<usize> {
        let b = self.take(4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    }
    fn f64(&mut self) -> Option<f64> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Some(f64::from_le_bytes(a))
    }
    fn point(&mut self) -> Option<Point3> {
        Some(Point3::new(self.f64()?, self.f64()?, self.f64()?))
    }
}

fn decode(bytes: &[u8], key: &MeshKey) -> Option<Decomposition> {
    let body_len = bytes.len().checked_sub(32)?;
    let (body, checksum) = bytes.split_at(body_len);
    if blake3::hash(body).as_bytes() != checksum {
        return None;
    }
    let mut r = Reader(body);
    if r.take(FORMAT.len())? != FORMAT || r.take(32)? != key.0 {
        return None;
    }
    let kind = DecompositionKind::from_code(r.u8()?)?;
    let count = r.u32()?;
    if count == 0 || count > MAX_FILE_PIECES {
        return None;
    }
    let mut pieces = Vec::with_capacity(count);
    for _ in 0..count {
        let piece = match r.u8()? {
            0 => {
                let center = r.point()?;
                let h = r.point()?;
                Piece::Cuboid {
                    center,
                    half_extents: Vector3::new(h.x, h.y, h.z),
                }
            }
            1 => {
                let n = r.u32()?;
                // Each point takes 24 bytes: a count larger than the rest of the file is corrupt.
                if n > MAX_FILE_POINTS || n.checked_mul(24)? > r.0.len() {
                    return None;
                }
                let points = (0..n).map(|_| r.point()).collect::<Option<Vec<_>>>()?;
                Piece::Hull { points }
            }
            _ => return None,
        };
        pieces.push(piece);
    }
    if !r.0.is_empty() {
        return None;
    }
    Decomposition::from_pieces(kind, pieces)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh() -> Mesh {
        Mesh::cuboid(&Vector3::new(0.4, 0.3, 0.2)).unwrap()
    }

    #[test]
    fn keys_follow_content_and_parameters() {
        let p = DecompositionParams::default();
        let a = MeshKey::new(&mesh(), &p);
        assert_eq!(a, MeshKey::new(&mesh(), &p));
        let scaled = mesh()
            .transformed(&sceneeval_geom::Matrix3::identity().scale(2.0), &Vector3::zeros())
            .unwrap();
        assert_ne!(a, MeshKey::new(&scaled, &p));
        let finer = DecompositionParams { resolution: 96, ..p };
        assert_ne!(a, MeshKey::new(&mesh(), &finer));
        assert_eq!(a.to_hex().len(), 64);
    }

    #[test]
    fn files_round_trip_bit_for_bit_and_corruption_is_detected() {
        let p = DecompositionParams::default();
        let key = MeshKey::new(&mesh(), &p);
        let d = Decomposition::of_mesh(&mesh(), &p);
        let bytes = encode(&d, &key);
        assert_eq!(decode(&bytes, &key), Some(d.clone()));
        // Another key, a flipped bit, a truncation: all rejected.
        let other = MeshKey([7; 32]);
        assert!(decode(&bytes, &other).is_none());
        let mut flipped = bytes.clone();
        flipped[50] ^= 1;
        assert!(decode(&flipped, &key).is_none());
        assert!(decode(&bytes[..bytes.len() - 1], &key).is_none());
        assert!(decode(&[], &key).is_none());
    }

    #[test]
    fn a_corrupt_file_is_decomposed_again_and_rewritten() {
        let dir = tempfile::tempdir().unwrap();
        let p = DecompositionParams::default();
        let key = MeshKey::new(&mesh(), &p);
        let path = dir.path().join(format!("{}.bin", key.to_hex()));
        fs::write(&path, b"not a cache file").unwrap();
        let cache = DecompositionCache::on_disk(dir.path()).unwrap();
        let d = cache.get(&mesh(), &p);
        assert_eq!(cache.stats().decomposed, 1);
        assert_eq!(decode(&fs::read(&path).unwrap(), &key).as_ref(), Some(&*d));
        // The second request is answered from memory.
        let _ = cache.get(&mesh(), &p);
        assert_eq!(cache.stats().memory_hits, 1);
        // No temporary file is left behind.
        let names: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
    }

    #[test]
    fn an_uncreatable_folder_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("file");
        fs::write(&file, b"x").unwrap();
        let err = DecompositionCache::on_disk(file.join("sub")).unwrap_err();
        assert!(matches!(err, PhysicsError::Cache { .. }), "{err}");
    }

    #[test]
    fn a_cache_path_that_is_not_a_regular_file_is_bypassed() {
        // A folder where the file would be: not read (nothing blocks or fails), decomposed
        // again, and the write over it fails with a warning only.
        let dir = tempfile::tempdir().unwrap();
        let p = DecompositionParams::default();
        let key = MeshKey::new(&mesh(), &p);
        fs::create_dir(dir.path().join(format!("{}.bin", key.to_hex()))).unwrap();
        let cache = DecompositionCache::on_disk(dir.path()).unwrap();
        let d = cache.get(&mesh(), &p);
        assert_eq!(cache.stats().decomposed, 1);
        assert_eq!(*d, Decomposition::of_mesh(&mesh(), &p));
        assert!(dir.path().join(format!("{}.bin", key.to_hex())).is_dir());
    }
}
