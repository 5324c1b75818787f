//! A layout optimiser on the scene API: simulated annealing moves a bed, two nightstands and a
//! desk in a 4 x 5 m bedroom until stated relations hold, asking `sceneeval-relations` and
//! `sceneeval-plausibility` after every move.
//!
//! The scene is built once ([`Layout::new`]): its room is prepared then (walls' solids, floor
//! triangles, openings), and so are the plausibility checks' floor pieces
//! ([`LayoutChecks`]). Each annealing step ([`Annealer::step`]) moves one object with
//! [`Scene::set_pose`], scores every goal by object index into a fixed array
//! ([`Layout::scores`]), and moves the object back if the step is rejected: no room is
//! prepared again and nothing is allocated (checked by `sceneeval-alloc-check`).

use std::f64::consts::{FRAC_PI_2, TAU};

use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Point2, Point3, Real, Side, Vector3};
use sceneeval_plausibility::{LayoutChecks, LayoutScratch, OutOfBoundsParams, PlausibilityError};
use sceneeval_relations::{
    ArchElement, DistanceBand, Relation, RelationError, RelationParams, SceneRelations,
};
use sceneeval_scene::{Category, RoomBuilder, Scene, SceneError};

/// The four pieces of furniture: name and half extents (metres).
pub const ITEMS: [(&str, [Real; 3]); 4] = [
    ("bed", [0.8, 1.0, 0.3]),
    ("left nightstand", [0.25, 0.2, 0.3]),
    ("right nightstand", [0.25, 0.2, 0.3]),
    ("desk", [0.6, 0.3, 0.375]),
];

const BED: usize = 0;
const LEFT_STAND: usize = 1;
const RIGHT_STAND: usize = 2;
const DESK: usize = 3;

/// Where an object stands: (x, y, yaw) on the floor, metres and radians.
pub type Placement = (Real, Real, Real);

/// Number of goals: 9 placement relations, then per object `inside_room`, "clear of the
/// door" and "in bounds" (plausibility), then "no overlap" for each of the 6 pairs.
pub const GOALS: usize = 9 + 3 * ITEMS.len() + 6;

/// What a [`Layout`] can fail on while being built or scored.
#[derive(Debug, thiserror::Error)]
pub enum LayoutError {
    /// The scene could not be built.
    #[error("building the scene: {0}")]
    Scene(#[from] SceneError),
    /// A relation could not be evaluated.
    #[error("evaluating a relation: {0}")]
    Relation(#[from] RelationError),
    /// The plausibility checks could not be prepared.
    #[error("preparing the plausibility checks: {0}")]
    Plausibility(#[from] PlausibilityError),
}

/// The bedroom with its four objects, and everything prepared once to score them.
#[derive(Debug)]
pub struct Layout {
    scene: Scene,
    relations: SceneRelations,
    /// "Clear of the door": `near(door)` with its range widened to "0.6 m or more".
    door: SceneRelations,
    checks: LayoutChecks,
    scratch: LayoutScratch,
    /// Where each object is: (x, y, yaw); z is its half height (standing on the floor).
    poses: [Placement; 4],
}

impl Layout {
    /// The bedroom (door in wall 0 at x in [2.6, 3.5]) with every object piled in the middle.
    ///
    /// # Errors
    /// [`LayoutError`] if the scene or the checks cannot be built (they always can).
    pub fn new() -> Result<Self, LayoutError> {
        let start = [(2.0, 2.5, 0.0), (2.1, 2.4, 0.0), (1.9, 2.6, 0.0), (2.0, 2.5, 0.0)];
        let mut builder = Scene::builder().room_builder(
            RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
                .wall_height(2.8)
                .wall_thickness(0.1)
                .door(0, [2.6, 3.5], [0.0, 2.1]),
        );
        for (i, (name, half)) in ITEMS.iter().enumerate() {
            let half = Vector3::from(*half);
            builder = builder.add_box(*name, Category::new(*name), half, pose(start[i], half.z));
        }
        let scene = builder.build()?;
        let params = RelationParams::default();
        let door = RelationParams {
            arch_near: DistanceBand::new(0.6, Real::INFINITY, 0.1),
            ..params
        };
        let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default())?;
        Ok(Layout {
            scratch: checks.scratch(),
            checks,
            scene,
            relations: SceneRelations::new(params)?,
            door: SceneRelations::new(door)?,
            poses: start,
        })
    }

    /// The scene as it stands.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The relation parameters (their `holds` threshold decides success).
    pub fn params(&self) -> &RelationParams {
        self.relations.params()
    }

    /// Object `i`'s (x, y, yaw).
    pub fn pose(&self, i: usize) -> Placement {
        self.poses[i]
    }

    /// Moves object `i` to (x, y) on the floor, turned by `yaw`.
    ///
    /// # Errors
    /// [`LayoutError::Scene`] for a non-finite pose.
    pub fn set(&mut self, i: usize, p: Placement) -> Result<(), LayoutError> {
        let half_z = ITEMS[i].1[2];
        self.scene.set_pose(i, pose(p, half_z))?;
        self.poses[i] = p;
        Ok(())
    }

    /// The label of goal `k` (see [`GOALS`]).
    pub fn label(k: usize) -> String {
        const PLACEMENT: [&str; 9] = [
            "bed against_wall",
            "left nightstand side_of(left) bed",
            "left nightstand next_to bed",
            "left nightstand against_wall",
            "right nightstand side_of(right) bed",
            "right nightstand next_to bed",
            "right nightstand against_wall",
            "desk against_wall",
            "desk across_from bed",
        ];
        let n = ITEMS.len();
        match k {
            k if k < 9 => PLACEMENT[k].to_owned(),
            k if k < 9 + n => format!("{} inside_room", ITEMS[k - 9].0),
            k if k < 9 + 2 * n => format!("{} clear of the door", ITEMS[k - 9 - n].0),
            k if k < 9 + 3 * n => format!("{} in bounds (plausibility)", ITEMS[k - 9 - 2 * n].0),
            k => {
                let (i, j) = PAIRS[k - 9 - 3 * n];
                format!("{} / {} do not overlap", ITEMS[i].0, ITEMS[j].0)
            }
        }
    }

    /// Every goal's score in [0, 1] into `out`, in the order of [`Layout::label`]. Scores
    /// objects by index, with the rooms and checks prepared once: no allocation.
    ///
    /// # Errors
    /// [`LayoutError::Relation`] (not expected: every index and relation is valid).
    pub fn scores(&mut self, out: &mut [Real; GOALS]) -> Result<(), LayoutError> {
        let (s, rel) = (&self.scene, &self.relations);
        let pair = |r: Relation, t: usize, a: usize| rel.pair(s, r, t, a).map(|e| e.score);
        let arch = |r: Relation, t: usize| rel.arch(s, r, t, &[]).map(|e| e.score);
        out[0] = arch(Relation::AgainstWall, BED)?;
        out[1] = pair(Relation::SideOf(Side::Left), LEFT_STAND, BED)?;
        out[2] = pair(Relation::NextTo, LEFT_STAND, BED)?;
        out[3] = arch(Relation::AgainstWall, LEFT_STAND)?;
        out[4] = pair(Relation::SideOf(Side::Right), RIGHT_STAND, BED)?;
        out[5] = pair(Relation::NextTo, RIGHT_STAND, BED)?;
        out[6] = arch(Relation::AgainstWall, RIGHT_STAND)?;
        out[7] = arch(Relation::AgainstWall, DESK)?;
        out[8] = pair(Relation::AcrossFrom, DESK, BED)?;
        let n = ITEMS.len();
        for i in 0..n {
            out[9 + i] = arch(Relation::InsideRoom, i)?;
            out[9 + n + i] = self
                .door
                .arch(s, Relation::NearArch(ArchElement::Door), i, &[])?
                .score;
            out[9 + 2 * n + i] = self.checks.in_bounds_ratio(&s.objects()[i], &mut self.scratch);
        }
        for (k, &(i, j)) in PAIRS.iter().enumerate() {
            let overlap = pair(Relation::InsideOf, i, j)?.max(pair(Relation::InsideOf, j, i)?);
            out[9 + 3 * n + k] = 1.0 - overlap;
        }
        Ok(())
    }

    /// The energy: the sum of the missing scores, `sum (1 - score)`.
    ///
    /// # Errors
    /// As [`Layout::scores`].
    pub fn energy(&mut self) -> Result<Real, LayoutError> {
        let mut s = [0.0; GOALS];
        self.scores(&mut s)?;
        Ok(s.iter().map(|v| 1.0 - v).sum())
    }
}

/// The six pairs of objects.
const PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// An upright object at (x, y) on the floor, its centre `half_z` up.
fn pose((x, y, yaw): Placement, half_z: Real) -> Isometry3 {
    pose_from_yaw(Point3::new(x, y, half_z), yaw)
}

/// xorshift64*: a tiny deterministic generator (no dependency needed for an example).
#[derive(Debug, Clone)]
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> Real {
        (self.next_u64() >> 11) as Real / (1u64 << 53) as Real
    }

    /// Roughly normal with standard deviation 1 (sum of four uniforms, rescaled).
    fn normal(&mut self) -> Real {
        let s: Real = (0..4).map(|_| self.uniform()).sum();
        (s - 2.0) * 3f64.sqrt()
    }

    fn below(&mut self, n: usize) -> usize {
        (self.uniform() * n as Real) as usize % n
    }
}

/// One simulated-annealing run: a seeded generator, a geometric temperature schedule over
/// `steps` steps, the current energy and the best layout seen.
#[derive(Debug, Clone)]
pub struct Annealer {
    rng: Rng,
    steps: usize,
    k: usize,
    t0: Real,
    t1: Real,
    energy: Real,
    best: (Real, [Placement; 4]),
}

impl Annealer {
    /// A run of `steps` steps from `layout`'s current state, with generator seed `seed`.
    ///
    /// # Errors
    /// As [`Layout::energy`].
    pub fn new(layout: &mut Layout, seed: u64, steps: usize) -> Result<Self, LayoutError> {
        let energy = layout.energy()?;
        Ok(Annealer {
            rng: Rng(0x5CE7_E7A1_0000_0000 ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)),
            steps,
            k: 0,
            t0: 2.0,
            t1: 1e-3,
            energy,
            best: (energy, layout.poses),
        })
    }

    /// One step: propose a move of one object (a jump to a random spot, a quarter turn, or a
    /// Gaussian shift shrinking with the temperature), score the layout, and keep the move by
    /// the Metropolis rule or move the object back. Allocates nothing.
    ///
    /// # Errors
    /// As [`Layout::energy`].
    pub fn step(&mut self, layout: &mut Layout) -> Result<(), LayoutError> {
        let (t0, t1) = (self.t0, self.t1);
        let t = t0 * (t1 / t0).powf(self.k as Real / self.steps.max(1) as Real);
        self.k += 1;
        let i = self.rng.below(ITEMS.len());
        let old = layout.pose(i);
        let mut p = old;
        let step = 0.05 + 0.5 * (t / t0).sqrt();
        let r = self.rng.uniform();
        if r < 0.1 {
            p.0 = 4.0 * self.rng.uniform();
            p.1 = 5.0 * self.rng.uniform();
        } else if r < 0.25 {
            let quarter = FRAC_PI_2 * (1 + self.rng.below(3)) as Real;
            p.2 = (p.2 + quarter).rem_euclid(TAU);
        } else {
            p.0 = (p.0 + step * self.rng.normal()).clamp(0.0, 4.0);
            p.1 = (p.1 + step * self.rng.normal()).clamp(0.0, 5.0);
        }
        layout.set(i, p)?;
        let e = layout.energy()?;
        if e <= self.energy || self.rng.uniform() < (-(e - self.energy) / t).exp() {
            self.energy = e;
            if e < self.best.0 {
                self.best = (e, layout.poses);
            }
        } else {
            layout.set(i, old)?;
        }
        Ok(())
    }

    /// Runs the remaining steps.
    ///
    /// # Errors
    /// As [`Annealer::step`].
    pub fn run(&mut self, layout: &mut Layout) -> Result<(), LayoutError> {
        while self.k < self.steps {
            self.step(layout)?;
        }
        Ok(())
    }

    /// The lowest energy seen and the poses that had it.
    pub fn best(&self) -> (Real, [Placement; 4]) {
        self.best
    }
}
