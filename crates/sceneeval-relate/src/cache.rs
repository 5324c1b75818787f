//! Prepared rooms kept by their text: the cache of a [`super::Session`].

use std::borrow::Borrow;
use std::cell::Cell;
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::Arc;

use sceneeval_scene::Room;

/// Prepared rooms kept by a key, at most a fixed number, the least recently used dropped
/// beyond that: preparing a [`Room`] from a `sceneeval_scene::RoomSpec` (walls cut into solids
/// around their openings, the floor triangulated) costs far more than scoring a relation in it,
/// so a front end that is handed the same room again and again (`sceneeval relate`'s rooms
/// written in place, the Python package's `room=` dicts) prepares it once.
///
/// The key is whatever identifies a room's content to the caller: `relate` keys by the room's
/// JSON text as written, the Python package by the JSON text of the dict it was given. Two
/// spellings of one room are two entries (both correct); one key is never two rooms.
/// The room asked for last is compared before the map is hashed, so a stream repeating one
/// room costs one comparison per query.
///
/// ```
/// use std::sync::Arc;
/// use sceneeval_relate::RoomCache;
/// use sceneeval_scene::RoomSpec;
/// let mut cache: RoomCache = RoomCache::new(8);
/// let text = r#"{"floor": [[0, 0], [4, 0], [4, 3], [0, 3]]}"#;
/// let build = || RoomSpec::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]).build();
/// let first = cache.get_or_build(text, build).unwrap();
/// let again = cache.get_or_build(text, build).unwrap();
/// assert!(Arc::ptr_eq(&first, &again));
/// assert_eq!(cache.built(), 1);
/// ```
#[derive(Debug)]
pub struct RoomCache<K = Arc<str>> {
    capacity: usize,
    clock: u64,
    rooms: HashMap<K, (Arc<Room>, Cell<u64>)>,
    /// The room asked for last, with its key. Its map entry's use stamp stays the newest
    /// while it is last, so it is never the one evicted.
    last: Option<(K, Arc<Room>)>,
    /// Rooms added so far.
    built: usize,
}

impl<K: Hash + Eq + Clone> RoomCache<K> {
    /// An empty cache holding at most `capacity` rooms (at least one).
    pub fn new(capacity: usize) -> Self {
        RoomCache {
            capacity: capacity.max(1),
            clock: 0,
            rooms: HashMap::new(),
            last: None,
            built: 0,
        }
    }

    /// The most rooms the cache holds.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// How many rooms the cache holds.
    pub fn len(&self) -> usize {
        self.rooms.len()
    }

    /// Whether the cache holds no room.
    pub fn is_empty(&self) -> bool {
        self.rooms.is_empty()
    }

    /// How many rooms have been added ([`RoomCache::insert`], or built by
    /// [`RoomCache::get_or_build`]) since the cache was made: the misses.
    pub fn built(&self) -> usize {
        self.built
    }

    /// The room kept under `key`, marked as used now.
    pub fn get<Q>(&mut self, key: &Q) -> Option<Arc<Room>>
    where
        K: Borrow<Q>,
        Q: Hash + Eq + ?Sized,
    {
        if let Some((last_key, room)) = &self.last
            && last_key.borrow() == key
        {
            return Some(Arc::clone(room));
        }
        self.clock += 1;
        let (key, (room, used)) = self.rooms.get_key_value(key)?;
        used.set(self.clock);
        let room = Arc::clone(room);
        self.last = Some((key.clone(), Arc::clone(&room)));
        Some(room)
    }

    /// Keeps `room` under `key` (replacing a room kept under it), dropping the least recently
    /// used room when the cache is full.
    pub fn insert(&mut self, key: K, room: Arc<Room>) {
        self.clock += 1;
        if self.rooms.len() >= self.capacity
            && !self.rooms.contains_key(&key)
            && let Some(oldest) = self
                .rooms
                .iter()
                .min_by_key(|(_, (_, used))| used.get())
                .map(|(k, _)| k.clone())
        {
            self.rooms.remove(&oldest);
        }
        self.built += 1;
        self.rooms
            .insert(key.clone(), (Arc::clone(&room), Cell::new(self.clock)));
        self.last = Some((key, room));
    }

    /// The room kept under `key`, else the room `build` makes, kept under `key` (a failure is
    /// not kept).
    ///
    /// # Errors
    /// The error of `build`.
    pub fn get_or_build<Q, E>(
        &mut self,
        key: &Q,
        build: impl FnOnce() -> Result<Room, E>,
    ) -> Result<Arc<Room>, E>
    where
        K: Borrow<Q> + for<'q> From<&'q Q>,
        Q: Hash + Eq + ?Sized,
    {
        if let Some(room) = self.get(key) {
            return Ok(room);
        }
        let room = Arc::new(build()?);
        self.insert(K::from(key), Arc::clone(&room));
        Ok(room)
    }
}

#[cfg(test)]
mod tests {
    use sceneeval_geom::Real;
    use sceneeval_scene::{RoomSpec, RoomSpecError};

    use super::*;

    #[test]
    fn the_room_cache_builds_each_key_once_and_evicts_the_least_recently_used() {
        const ROOM: &str = r#"{"floor":[[0,0],[4,0],[4,3],[0,3]]}"#;
        let other = r#"{"floor":[[0,0],[5,0],[5,3],[0,3]]}"#;
        let third = r#"{"floor":[[0,0],[6,0],[6,3],[0,3]]}"#;
        let build = |x: Real| move || RoomSpec::new(vec![[0.0, 0.0], [x, 0.0], [x, 3.0], [0.0, 3.0]]).build();
        let mut cache: RoomCache = RoomCache::new(2);
        assert!(cache.is_empty());
        let a = cache.get_or_build(ROOM, build(4.0)).unwrap();
        let again = cache.get_or_build(ROOM, build(4.0)).unwrap();
        assert!(Arc::ptr_eq(&a, &again));
        assert_eq!(cache.built(), 1);
        cache.get_or_build(other, build(5.0)).unwrap();
        // ROOM was used before `other`: adding a third evicts ROOM, keeps `other`.
        cache.get_or_build(third, build(6.0)).unwrap();
        assert_eq!((cache.len(), cache.built(), cache.capacity()), (2, 3, 2));
        let kept = cache.get_or_build(other, build(5.0)).unwrap();
        assert_eq!(cache.built(), 3, "other stayed cached");
        // The 5 m room's floor: 15 m^2.
        assert!((kept.floor().area() - 15.0).abs() < 1e-12);
        cache.get_or_build(ROOM, build(4.0)).unwrap();
        assert_eq!(cache.built(), 4, "ROOM was evicted and built again");
        // `third` was used before `other`'s last use: it went, `other` stays.
        assert!(cache.get(other).is_some());
        assert!(cache.get(third).is_none());
        let bad = cache.get_or_build("bad", || RoomSpec::new(vec![[0.0, 0.0], [1.0, 0.0]]).build());
        assert!(matches!(bad, Err(RoomSpecError::Room { .. })));
        assert_eq!(cache.len(), 2, "failures are not kept");
        assert!(cache.get("bad").is_none());
        // A capacity of 0 still keeps the room in use.
        let mut tiny: RoomCache<String> = RoomCache::new(0);
        tiny.insert("a".into(), Arc::clone(&a));
        assert!(tiny.get("a").is_some());
        assert_eq!(tiny.capacity(), 1);
    }
}
