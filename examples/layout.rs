//! A layout optimiser's model on the scene API: a bed, two nightstands and a desk in a 4 x 5 m
//! bedroom, the goals they should meet (relations of `sceneeval-relations` and checks of
//! `sceneeval-plausibility`), and two optimisers placing them: simulated annealing
//! ([`Annealer`]), which only samples the scores, and gradient descent ([`Descent`], Adam on
//! the goals' gradients).
//!
//! The scene is built once ([`Layout::new`]): its room is prepared then (walls' solids, floor
//! triangles, openings), and so are the plausibility checks' floor pieces and door boxes
//! ([`LayoutChecks`]). Each annealing step ([`Annealer::step`]) moves one object with
//! [`Scene::set_pose`], scores every goal by object index into a fixed array
//! ([`Layout::scores`]), and moves the object back if the step is rejected; each descent step
//! ([`Descent::step`]) takes every goal's score and gradient ([`Layout::gradient`]) and moves
//! every object. No room is prepared again and nothing is allocated (checked by
//! `sceneeval-alloc-check`).

use std::f64::consts::{FRAC_PI_2, TAU};

use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Point2, Point3, Real, Side, Vector3};
use sceneeval_plausibility::{Contact, LayoutChecks, LayoutScratch, OutOfBoundsParams, PlausibilityError};
use sceneeval_relations::grad::{self, BoxGrad};
use sceneeval_relations::{
    ArchElement, DistanceBand, ObjectGeom, Relation, RelationError, RelationParams, SceneRelations,
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
/// door" and "in bounds" (plausibility), then "no collision" for each of the 6 pairs.
pub const GOALS: usize = 9 + 3 * ITEMS.len() + 6;

/// One goal: what is scored, on which objects (indices into [`ITEMS`]).
#[derive(Debug, Clone, Copy)]
enum Goal {
    /// An object-architecture relation of an object.
    Arch(Relation, usize),
    /// `near(door)` widened to "0.6 m or more" (the layout's second parameter set).
    ClearOfDoor(usize),
    /// A two-object relation: target, anchor.
    Pair(Relation, usize, usize),
    /// The plausibility out-of-bounds check (no gradient).
    InBounds(usize),
    /// The plausibility contact check of a pair: 1 apart or resting, below 0.5 and falling
    /// with the penetration depth when colliding.
    NoCollision(usize, usize),
}

impl Goal {
    /// The objects the goal scores (indices into [`ITEMS`]).
    fn objects(self) -> [Option<usize>; 2] {
        match self {
            Goal::Arch(_, t) | Goal::ClearOfDoor(t) | Goal::InBounds(t) => [Some(t), None],
            Goal::Pair(_, t, a) => [Some(t), Some(a)],
            Goal::NoCollision(i, j) => [Some(i), Some(j)],
        }
    }
}

/// Every goal, in the order of [`Layout::label`].
const GOAL_LIST: [Goal; GOALS] = {
    use Goal::*;
    use Relation as R;
    [
        Arch(R::AgainstWall, BED),
        Pair(R::SideOf(Side::Left), LEFT_STAND, BED),
        Pair(R::NextTo, LEFT_STAND, BED),
        Arch(R::AgainstWall, LEFT_STAND),
        Pair(R::SideOf(Side::Right), RIGHT_STAND, BED),
        Pair(R::NextTo, RIGHT_STAND, BED),
        Arch(R::AgainstWall, RIGHT_STAND),
        Arch(R::AgainstWall, DESK),
        Pair(R::AcrossFrom, DESK, BED),
        Arch(R::InsideRoom, 0),
        Arch(R::InsideRoom, 1),
        Arch(R::InsideRoom, 2),
        Arch(R::InsideRoom, 3),
        ClearOfDoor(0),
        ClearOfDoor(1),
        ClearOfDoor(2),
        ClearOfDoor(3),
        InBounds(0),
        InBounds(1),
        InBounds(2),
        InBounds(3),
        NoCollision(PAIRS[0].0, PAIRS[0].1),
        NoCollision(PAIRS[1].0, PAIRS[1].1),
        NoCollision(PAIRS[2].0, PAIRS[2].1),
        NoCollision(PAIRS[3].0, PAIRS[3].1),
        NoCollision(PAIRS[4].0, PAIRS[4].1),
        NoCollision(PAIRS[5].0, PAIRS[5].1),
    ]
};

/// The score of a "no collision" goal from the pair's contact: 1 unless colliding, then
/// `0.5 (1 - depth / 0.5 m)` (at least 0; a mesh collision without a depth scores 0), so that
/// the goal holds exactly when the pair does not collide; and the score's derivative with
/// respect to the depth.
fn no_collision(c: &Contact) -> (Real, Real) {
    if !c.colliding {
        return (1.0, 0.0);
    }
    match c.depth {
        Some(d) if d < 0.5 => (0.5 * (1.0 - d / 0.5), -1.0),
        _ => (0.0, 0.0),
    }
}

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

    /// The layout as text (each object's centre and yaw, each goal's score and whether it
    /// holds) and whether every goal holds.
    ///
    /// # Errors
    /// As [`Layout::scores`].
    pub fn report(&mut self) -> Result<(String, bool), LayoutError> {
        use std::fmt::Write;
        let mut text = String::new();
        for (i, (name, _)) in ITEMS.iter().enumerate() {
            let (x, y, yaw) = self.pose(i);
            let _ = writeln!(
                text,
                "{name:<17} centre ({x:.2}, {y:.2}) m, yaw {:>4.0} deg",
                yaw.to_degrees()
            );
        }
        text.push('\n');
        let mut scores = [0.0; GOALS];
        self.scores(&mut scores)?;
        let mut ok = true;
        for (k, s) in scores.iter().enumerate() {
            let holds = self.params().holds(*s);
            ok &= holds;
            let verdict = if holds { "holds" } else { "FAILS" };
            let _ = writeln!(text, "{:<50} {s:.3}  {verdict}", Layout::label(k));
        }
        let _ = write!(text, "\nall goals hold: {}", if ok { "yes" } else { "no" });
        Ok((text, ok))
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
                format!("{} / {} do not collide (plausibility)", ITEMS[i].0, ITEMS[j].0)
            }
        }
    }

    /// Every goal's score in [0, 1] into `out`, in the order of [`Layout::label`]. Scores
    /// objects by index, with the rooms and checks prepared once: no allocation.
    ///
    /// # Errors
    /// [`LayoutError::Relation`] (not expected: every index and relation is valid).
    pub fn scores(&mut self, out: &mut [Real; GOALS]) -> Result<(), LayoutError> {
        let s = &self.scene;
        for (slot, goal) in out.iter_mut().zip(GOAL_LIST) {
            *slot = match goal {
                Goal::Arch(r, t) => self.relations.arch(s, r, t, &[])?.score,
                Goal::ClearOfDoor(t) => {
                    self.door
                        .arch(s, Relation::NearArch(ArchElement::Door), t, &[])?
                        .score
                }
                Goal::Pair(r, t, a) => self.relations.pair(s, r, t, a)?.score,
                Goal::InBounds(t) => self.checks.in_bounds_ratio(&s.objects()[t], &mut self.scratch),
                Goal::NoCollision(i, j) => {
                    no_collision(&self.checks.contact(&s.objects()[i], &s.objects()[j])).0
                }
            };
        }
        Ok(())
    }

    /// Every goal's score into `out` (as [`Layout::scores`]) and the gradient of the energy
    /// (the sum of the missing scores) with respect to each object's `(x, y, yaw)` into
    /// `d_energy`; returns the energy. The out-of-bounds goal has no gradient (its companion
    /// `inside_room` has). No allocation.
    ///
    /// # Errors
    /// [`LayoutError::Relation`] (not expected: every index and relation is valid).
    pub fn gradient(
        &mut self,
        out: &mut [Real; GOALS],
        d_energy: &mut [[Real; 3]; 4],
    ) -> Result<Real, LayoutError> {
        let s = &self.scene;
        let rooms = s.rooms();
        let geom = |i: usize| ObjectGeom::from_object(&s.objects()[i]);
        *d_energy = [[0.0; 3]; 4];
        // The energy falls as a score rises: subtract each score's gradient.
        let mut take = |i: usize, g: &BoxGrad| {
            d_energy[i][0] -= g.center.x;
            d_energy[i][1] -= g.center.y;
            d_energy[i][2] -= g.yaw;
        };
        let params = *self.relations.params();
        let door = *self.door.params();
        for (slot, goal) in out.iter_mut().zip(GOAL_LIST) {
            *slot = match goal {
                Goal::Arch(r, t) => {
                    let g = grad::arch_rooms(r, &geom(t), rooms, &params)?;
                    take(t, &g.target);
                    g.score
                }
                Goal::ClearOfDoor(t) => {
                    let g = grad::arch_rooms(Relation::NearArch(ArchElement::Door), &geom(t), rooms, &door)?;
                    take(t, &g.target);
                    g.score
                }
                Goal::Pair(r, t, a) => {
                    let g = grad::pair(r, &geom(t), &geom(a), &params)?;
                    take(t, &g.target);
                    take(a, &g.anchor);
                    g.score
                }
                Goal::InBounds(t) => self.checks.in_bounds_ratio(&s.objects()[t], &mut self.scratch),
                Goal::NoCollision(i, j) => {
                    let c = self.checks.contact(&s.objects()[i], &s.objects()[j]);
                    let (score, slope) = no_collision(&c);
                    if let Some((gi, gj)) = c.gradient.filter(|_| slope != 0.0) {
                        take(i, &(gi * slope));
                        take(j, &(gj * slope));
                    }
                    score
                }
            };
        }
        Ok(out.iter().map(|v| 1.0 - v).sum())
    }

    /// The energy: the sum of the missing scores, `sum (1 - score)`.
    ///
    /// # Errors
    /// As [`Layout::scores`].
    pub fn energy(&mut self) -> Result<Real, LayoutError> {
        Ok(self.energy_and_verdict()?.0)
    }

    /// The energy and whether every goal holds.
    ///
    /// # Errors
    /// As [`Layout::scores`].
    pub fn energy_and_verdict(&mut self) -> Result<(Real, bool), LayoutError> {
        let mut s = [0.0; GOALS];
        self.scores(&mut s)?;
        let params = self.relations.params();
        Ok((
            s.iter().map(|v| 1.0 - v).sum(),
            s.iter().all(|v| params.holds(*v)),
        ))
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
    /// The first step after which every goal held.
    solved_at: Option<usize>,
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
            solved_at: None,
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
        let (e, holds) = layout.energy_and_verdict()?;
        if e <= self.energy || self.rng.uniform() < (-(e - self.energy) / t).exp() {
            self.energy = e;
            if e < self.best.0 {
                self.best = (e, layout.poses);
            }
            if holds && self.solved_at.is_none() {
                self.solved_at = Some(self.k);
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

    /// The number of steps after which every goal first held (each step scores every goal
    /// once), if they have.
    pub fn solved_at(&self) -> Option<usize> {
        self.solved_at
    }
}

/// Gradient descent on the energy: Adam (Kingma and Ba) on every object's `(x, y, yaw)` with
/// the goals' analytic gradients ([`Layout::gradient`]), from a random layout. When a start
/// has not placed every goal within [`Descent::RESTART_AFTER`] steps, the objects of the
/// goals that fail are placed at random again (the others stay where the descent put them)
/// and Adam starts afresh. Each step moves every object.
#[derive(Debug, Clone)]
pub struct Descent {
    rng: Rng,
    /// Adam's first and second moment estimates, and the steps taken since the start.
    m: [[Real; 3]; 4],
    v: [[Real; 3]; 4],
    t: usize,
    /// Steps taken over every start.
    steps: usize,
    /// Random starts made.
    starts: usize,
    best: (Real, [Placement; 4]),
}

impl Descent {
    /// Step sizes: metres along x and y, radians of yaw.
    pub const RATE: [Real; 3] = [0.04, 0.04, 0.08];
    /// Steps from one start before the next.
    pub const RESTART_AFTER: usize = 100;
    const BETA1: Real = 0.9;
    const BETA2: Real = 0.999;

    /// A descent with generator seed `seed`, from a random layout (moves `layout`'s objects).
    ///
    /// # Errors
    /// As [`Layout::set`].
    pub fn new(layout: &mut Layout, seed: u64) -> Result<Self, LayoutError> {
        let mut d = Descent {
            rng: Rng(0x6AD1_E47D_0000_0000 ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)),
            m: [[0.0; 3]; 4],
            v: [[0.0; 3]; 4],
            t: 0,
            steps: 0,
            starts: 0,
            best: (Real::INFINITY, layout.poses),
        };
        d.restart(layout, [true; 4])?;
        Ok(d)
    }

    /// Places the objects `moved` marks at random (uniform over the floor, any yaw) and
    /// resets Adam.
    fn restart(&mut self, layout: &mut Layout, moved: [bool; 4]) -> Result<(), LayoutError> {
        for (i, _) in moved.iter().enumerate().filter(|(_, m)| **m) {
            let p = (
                4.0 * self.rng.uniform(),
                5.0 * self.rng.uniform(),
                TAU * self.rng.uniform(),
            );
            layout.set(i, p)?;
        }
        self.m = [[0.0; 3]; 4];
        self.v = [[0.0; 3]; 4];
        self.t = 0;
        self.starts += 1;
        Ok(())
    }

    /// One step: every goal's score and gradient, then (unless every goal holds, which this
    /// returns) an Adam step on every object, or a new random start after
    /// [`Descent::RESTART_AFTER`] steps. Allocates nothing.
    ///
    /// # Errors
    /// As [`Layout::gradient`].
    pub fn step(&mut self, layout: &mut Layout) -> Result<bool, LayoutError> {
        let mut scores = [0.0; GOALS];
        let mut d = [[0.0; 3]; 4];
        let energy = layout.gradient(&mut scores, &mut d)?;
        self.steps += 1;
        if energy < self.best.0 {
            self.best = (energy, layout.poses);
        }
        let params = *layout.params();
        if scores.iter().all(|s| params.holds(*s)) {
            return Ok(true);
        }
        if self.t >= Self::RESTART_AFTER {
            // The objects of the goals that fail start again.
            let mut moved = [false; 4];
            for (goal, s) in GOAL_LIST.iter().zip(&scores) {
                if !params.holds(*s) {
                    for i in goal.objects().into_iter().flatten() {
                        moved[i] = true;
                    }
                }
            }
            self.restart(layout, moved)?;
            return Ok(false);
        }
        self.t += 1;
        let t = self.t as i32;
        let (c1, c2) = (1.0 - Self::BETA1.powi(t), 1.0 - Self::BETA2.powi(t));
        for (i, g) in d.iter().enumerate() {
            let (x, y, yaw) = layout.pose(i);
            let mut p = [x, y, yaw];
            for k in 0..3 {
                self.m[i][k] = Self::BETA1 * self.m[i][k] + (1.0 - Self::BETA1) * g[k];
                self.v[i][k] = Self::BETA2 * self.v[i][k] + (1.0 - Self::BETA2) * g[k] * g[k];
                let (mh, vh) = (self.m[i][k] / c1, self.v[i][k] / c2);
                p[k] -= Self::RATE[k] * mh / (vh.sqrt() + 1e-8);
            }
            layout.set(
                i,
                (p[0].clamp(0.0, 4.0), p[1].clamp(0.0, 5.0), p[2].rem_euclid(TAU)),
            )?;
        }
        Ok(false)
    }

    /// Steps until every goal holds (returns `true`) or `max_steps` steps in all.
    ///
    /// # Errors
    /// As [`Descent::step`].
    pub fn run(&mut self, layout: &mut Layout, max_steps: usize) -> Result<bool, LayoutError> {
        while self.steps < max_steps {
            if self.step(layout)? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Steps taken (each scores every goal with its gradient once) and random starts made.
    pub fn work(&self) -> (usize, usize) {
        (self.steps, self.starts)
    }

    /// The lowest energy seen and the poses that had it.
    pub fn best(&self) -> (Real, [Placement; 4]) {
        self.best
    }
}
