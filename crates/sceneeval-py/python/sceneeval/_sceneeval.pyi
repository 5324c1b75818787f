"""Type stubs of the Rust extension module ``sceneeval._sceneeval``.

The docstrings here are the functions' runtime docstrings (a test checks that they agree).
"""

import os
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from . import stats as stats

__version__: str
OBJECT_OBJECT_RELATIONS: List[str]
OBJECT_ARCHITECTURE_RELATIONS: List[str]
DEFAULT_VLM_TIMEOUT_SECONDS: float
"""Seconds one VLM request attempt may take unless ``vlm["timeout_s"]`` says otherwise."""
DEFAULT_VLM_CONCURRENCY: int
"""VLM requests in flight at once over a run unless ``vlm["concurrency"]`` says otherwise."""
DEFAULT_RENDER_SIZE: int
"""Side of the object views shown to the VLM, pixels, unless ``vlm["render_size"]`` says otherwise."""

BoxLike = Union[Sequence[float], Mapping[str, Any]]
"""A box: ``(cx, cy, cz, hx, hy, hz, yaw)`` or a dict with the keys of ``sceneeval relate``
(``center``, ``half_size``, and ``yaw`` or ``rotation``)."""

RoomLike = Mapping[str, Any]
"""A room: a dict with the keys of ``sceneeval relate`` (``floor``, ``floor_z``, ``height``,
``wall_thickness``, ``openings``)."""

ParamValue = Union[float, int, str, Tuple[float, Optional[float], float], Mapping[str, Optional[float]]]
PathLike = Union[str, "os.PathLike[str]"]

class SceneEvalError(Exception):
    """A scene, asset, annotation or result file could not be read, evaluated or written. The message names the file and, where it applies, the JSON pointer, the object id or the asset."""

def relation(
    name: str,
    target: Optional[BoxLike],
    anchor: Optional[BoxLike] = None,
    *,
    side: Optional[str] = None,
    arch: Optional[str] = None,
    targets: Optional[Sequence[BoxLike]] = None,
    room: Optional[RoomLike] = None,
    reference: bool = False,
    **params: ParamValue,
) -> float:
    """The score in [0, 1] of one spatial relation (it holds when the score is above 0.5).

    name: one of the 23 relations (see relation_names()); side_of, side_region and
    long_short_side_of take side= (left, right, front, back, top, bottom; long or short),
    the distance relations next_to, near, across_from and far take arch= (wall, door, window)
    to relate an object to the room. The name may carry its argument: "side_of(left)".

    Object-object relations score target relative to anchor; surround scores targets=[...]
    around anchor (target is None); object-architecture relations score target in room.
    A box is (cx, cy, cz, hx, hy, hz, yaw) in metres and radians (yaw 0: front faces -y) or a
    dict with the keys of `sceneeval relate` (center, half_size, yaw or rotation); a room is a
    dict with its room keys (floor, floor_z, height, wall_thickness, openings). A room is
    prepared (walls cut around their openings, floor triangulated) once and kept, with the
    last 64 distinct rooms given (found by their content), so a loop asking about one room
    prepares it once; relation_batch shares these rooms.

    reference=True selects every reference-parity switch (RelationParams::reference);
    any other keyword sets one parameter by its name in relation_params(), e.g.
    side_of_margin=0.3 or near=(0.4, 1.2, 0.2) (min_m, max_m, sigma_m).

    Raises ValueError for an unknown name, a missing or extra operand or argument, a NaN or
    infinite number, or a bad parameter, with the message `sceneeval relate` gives.
    """

@overload
def relation_batch(
    name: str,
    targets: npt.NDArray[np.float64],
    anchors: Optional[npt.NDArray[np.float64]] = None,
    *,
    side: Optional[str] = None,
    arch: Optional[str] = None,
    room: Optional[RoomLike] = None,
    reference: bool = False,
    grad: Literal[False] = False,
    **params: ParamValue,
) -> npt.NDArray[np.float64]:
    """The scores of one relation for N boxes (or N groups of boxes), as a float64 array of
    shape (N,).

    targets: a float64 array of shape (N, 7), one box (cx, cy, cz, hx, hy, hz, yaw) per row.
    Object-object relations take anchors of shape (N, 7) (row i is the anchor of target i)
    or (1, 7) (one anchor for every target); object-architecture relations take room (a dict
    as for relation()) instead. surround takes N groups of K targets, targets of shape
    (N, K, 7), and anchors of shape (N, 7) or (1, 7): score i is surround of the K boxes
    of group i around anchor i. name, side, arch, reference and the parameter keywords are as
    for relation().

    The scores equal relation() called row by row (group by group for surround). Computed
    with the GIL released.

    grad=True returns the scores with their gradients, (scores, d_targets, d_anchors):
    ``d_targets[i]`` and ``d_anchors[i]`` are the derivatives of score i with respect to the seven
    numbers of its target and anchor rows, in the rows' order (cx, cy, cz, hx, hy, hz, yaw),
    float64 arrays of shape (N, 7) (d_targets (N, K, 7) for surround; d_anchors has one row
    per score also when one anchor row is shared: sum it for that row's gradient).
    Object-architecture relations (room=) return (scores, d_targets): the room is fixed. The
    scores are those of grad=False, bit for bit; the derivatives are exact where the score is
    differentiable and one-sided at its kinks (see sceneeval_relations::grad in the Rust
    documentation).

    Raises ValueError when an array is not a float64 numpy array of the right shape, holds a
    NaN or infinite number, or when the relation or its arguments are wrong.
    """

@overload
def relation_batch(
    name: str,
    targets: npt.NDArray[np.float64],
    anchors: npt.NDArray[np.float64],
    *,
    side: Optional[str] = None,
    arch: Optional[str] = None,
    room: None = None,
    reference: bool = False,
    grad: Literal[True],
    **params: ParamValue,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
@overload
def relation_batch(
    name: str,
    targets: npt.NDArray[np.float64],
    anchors: None = None,
    *,
    side: Optional[str] = None,
    arch: Optional[str] = None,
    room: RoomLike,
    reference: bool = False,
    grad: Literal[True],
    **params: ParamValue,
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def relation_names() -> List[str]:
    """Every relation with every argument, in the printed form relation() accepts (side_of(left), next_to(wall), ...)."""

def relation_params(*, reference: bool = False, **params: ParamValue) -> Dict[str, Any]:
    """The predicates' parameters as a dict: the defaults (or the reference's with reference=True) with the keyword arguments given applied and validated. Lengths are metres, angles degrees."""

class Scene:
    """A scene: objects (boxes or meshes) and rooms with walls, doors and windows.

    Build one from boxes with Scene.from_boxes or load a sceneState file with load_scene.
    Objects can be moved (set_pose, set_boxes), for example in an optimisation loop; a scene
    may be shared between threads (a move waits for the computations under way).
    """

    @staticmethod
    def from_boxes(
        boxes: npt.NDArray[np.float64],
        room: Optional[RoomLike] = None,
        *,
        rooms: Optional[Sequence[RoomLike]] = None,
        categories: Optional[Sequence[str]] = None,
        ids: Optional[Sequence[str]] = None,
        name: Optional[str] = None,
        id: Optional[str] = None,
    ) -> "Scene":
        """A scene of box objects in one room or several.

        boxes: a float64 array of shape (N, 7), one object per row (cx, cy, cz, hx, hy, hz,
        yaw): centre, half extents (metres) and yaw (radians, yaw 0: front faces -y).
        room: a dict as for relation(): the floor polygon, wall height and thickness, doors
        and windows (openings); its id is "room". rooms: several such dicts instead (ids
        "room_0", "room_1", ...); a room dict may also carry its id (the key id), used by
        Scene.relation's floors= and in the plausibility report. categories: one per object
        (used by the support and accessibility tables); ids: one per object (default `box_0`,
        `box_1`, ...); name: the scene's name (id=, its old spelling, warns).

        Raises ValueError for a bad array, a bad room or a bad box.
        """
    @property
    def name(self) -> Optional[str]:
        """The scene's name (for a file, its stem: `scene_12`), if it has one."""
    @property
    def id(self) -> Optional[str]:
        """The scene's name: Scene.name, with a DeprecationWarning (scene_id means the benchmark
        id, `12`; the name is the file stem)."""
    @property
    def objects(self) -> List[Dict[str, Any]]:
        """Every object as a dict: id, index, model_id, category, description, is_box, center, size (full width, depth, height), yaw, front (world direction of its front), asset_front (the front its file declared, or None), scale, support_type, functional_sides."""
    @property
    def rooms(self) -> List[Dict[str, Any]]:
        """Every room as a dict (id, kind, floor_id, floor_z, ceiling_z, floor_area, floor, walls), each wall with its openings."""
    def info(self) -> Dict[str, Any]:
        """The scene as one dict with scene, objects and rooms: what `sceneeval inspect --json` prints, without the file."""
    def boxes(self) -> npt.NDArray[np.float64]:
        """The objects' boxes as a float64 array of shape (N, 7): centre, half extents, yaw."""
    def set_pose(self, object: Union[str, int], center: Sequence[float], yaw: float) -> None:
        """Moves one object: its box's centre to center (x, y, z) and its yaw to yaw (radians
        about +z; the object is then upright), as boxes() reports them. object: the object's
        id (str) or its position in objects (int). For a box object the centre is the box's;
        for a mesh object, the centre of its mesh bounds. Everything computed afterwards
        (relations, plausibility, objects, boxes) sees the object where it now is.

        Raises ValueError for an unknown id, an index out of range, or a NaN or infinite
        number (the object then stays where it was).
        """
    def set_boxes(self, boxes: npt.NDArray[np.float64]) -> None:
        """Moves every object at once: boxes is a float64 array of shape (N, 7) as boxes()
        returns it, one row per object in order; each object's box centre and yaw are set
        from its row as set_pose does. The half extents of a row must be the object's (an
        object cannot be resized): `b = scene.boxes(); b[:, 0] += 0.1; scene.set_boxes(b)`
        moves everything 10 cm along x.

        Raises ValueError for an array of the wrong shape or dtype, a NaN or infinite number,
        or half extents that differ from the object's; then no object is moved.
        """
    def plausibility(
        self,
        *,
        plan: Optional[str] = None,
        preset: Optional[str] = None,
        metrics: Optional[Sequence[str]] = None,
    ) -> Dict[str, Any]:
        """Runs the geometry-only plausibility metrics and returns the report as in eval.json.

        plan: as for evaluate() ("geometry", the default: every geometry metric; a
        comma-separated metric list; or the path of a plan file), without text-fidelity
        metrics. preset: "default" or "reference" (every reference-parity switch), replacing
        a plan file's. metrics: run only these (collision, support, navigability,
        accessibility, out_of_bounds, opening_clearance).
        The report holds the scene-level summary and each metric's per-object evidence.
        Computed with the GIL released.
        """
    def stability(
        self,
        *,
        plan: Optional[Union[str, PathLike]] = None,
        preset: Optional[str] = None,
        weld: Optional[str] = None,
        vlm: Optional[Mapping[str, Any]] = None,
        assets: Optional[Mapping[str, PathLike]] = None,
    ) -> Dict[str, Any]:
        """Simulates the scene under gravity (the stability metric) and returns its report as
        eval.json's report.stability: per object id, stable, displacement_m, rotation_rad,
        welded, weld_reason, final_pose, ...; and frac_unstable (unstable over the objects free
        to move; None when none was, with frac_unstable_missing saying why).

        plan: as for evaluate() ("geometry", the default: the built-in parameters; "full"; a
        metric list; or a plan file, JSON or TOML) and preset ("default" or "reference"): the
        plan's stability section, reading options, limits and time budget apply, as
        `sceneeval settle --plan` takes it; weld: "architectural" (default: objects on walls and ceilings are fixed in place),
        "penetration", "combined" or "none", replacing the plan's. Support types come from
        what the objects state, then (with vlm) the VLM's answer for each object that states
        none, then the category tables, as evaluate() gets them. vlm: the OpenAI-compatible
        endpoint asked, the same dict as evaluate()'s vlm (base_url, model, api_key_env,
        cache, render_size, ...); its answers are kept in vlm["cache"] when given (else for
        this call only, as `sceneeval settle` keeps them), and the report then has placement: for each object, where
        its support type came from and why (eval.json's report.placement). assets: as for
        load_scene, the library the VLM's object views are drawn from (their materials;
        default: plain colours). The scene is not moved. Computed with the GIL released.

        Raises ValueError for a bad plan, weld mode, vlm dict or assets mapping (the message
        starts with the keyword at fault, `vlm["model"]: ...`), SceneEvalError when the
        scene cannot be simulated (no room, hence no floor; the time budget ran out).
        """
    def settle(
        self,
        *,
        plan: Optional[Union[str, PathLike]] = None,
        preset: Optional[str] = None,
        weld: Optional[str] = None,
        vlm: Optional[Mapping[str, Any]] = None,
        assets: Optional[Mapping[str, PathLike]] = None,
    ) -> Tuple["Scene", Dict[str, Any]]:
        """Simulates the scene as stability() does and returns (settled, report): a new Scene
        with every object at its pose after the simulation (fixed objects where they were),
        and the report. This scene is not moved. Arguments and errors as stability().
        """
    def relation(
        self,
        name: str,
        target: Optional[str],
        anchor: Optional[str] = None,
        *,
        side: Optional[str] = None,
        arch: Optional[str] = None,
        targets: Optional[Sequence[str]] = None,
        floors: Optional[Sequence[str]] = None,
        reference: bool = False,
        **params: ParamValue,
    ) -> float:
        """The score of a relation between objects of this scene, by object id.

        As relation(), but the objects' meshes are used where the predicate uses geometry, and
        the architecture is the scene's rooms (floors= restricts the floor-based relations to
        some floors or rooms). surround takes targets=[id, ...] with target None.
        """
    def __len__(self) -> int: ...

def load_scene(
    path: PathLike, assets: Optional[Mapping[str, PathLike]] = None, *, strict: bool = False
) -> Scene:
    """Loads a sceneState file (`scene_<ID>.json`).

    assets maps a model id prefix to its folder, {"objaverse": "/data/objathor-assets"}; the
    folder layout is chosen from the prefix as by `sceneeval evaluate --assets`, or given as
    "LAYOUT:folder" (3d-future, objathor, hssd, layoutvlm, plain). Read with the GIL released.
    Keys the sceneState format does not have (a misspelt key is read as absent) are each logged
    as a warning; strict=True raises SceneEvalError listing them instead.

    Raises SceneEvalError naming the file, the JSON pointer and the asset when the scene
    cannot be read, and ValueError for a bad assets mapping.
    """

def compare(
    runs: Sequence[PathLike],
    *,
    names: Optional[Sequence[str]] = None,
    paired: bool = False,
    against_first: bool = False,
    ci: Optional[float] = None,
    alpha: float = 0.05,
    rank: Literal["tested", "mean"] = "tested",
    failed: Literal["skip", "worst"] = "skip",
    by_difficulty: bool = False,
) -> List[Dict[str, Any]]:
    """Compares the runs (output folders of `evaluate`) as `sceneeval compare` does.

    With `paired=True`, one dict per pair of runs (each against the first with
    `against_first=True`) and metric column: `kind` (`paired`), `a`, `b`, `metric`, `n`,
    `mean_diff` (b - a, percentage points), `diff_low`, `diff_high` (the paired bootstrap
    interval at `ci`, default 0.95), `p_value` (two-sided Wilcoxon signed-rank; `None` from
    fewer than two non-zero differences, `note` says why), `p_holm` (Holm across the pair's
    columns), `better`, `method`, `zeros`, `favours`, `note`; and one per pair and fidelity
    metric with `kind` `mcnemar` (McNemar's exact test on the specs both judged, `a_only`,
    `b_only`). Without it, one dict per run and column: `group`, `scenes`, `run`, `column`,
    `better`, `value`, `n`, `ci_low`, `ci_high`, `rank`, `points`, `missing`, `failed`.
    `rank` is `tested` or `mean`, `failed` `skip` or `worst` (docs/formats.md).

    Raises SceneEvalError when a folder cannot be read, ValueError for a bad option (the
    message starts with the keyword).
    """

def ensemble(
    runs: Sequence[PathLike],
    out: PathLike,
    *,
    annotations: Optional[PathLike] = None,
) -> Dict[str, Any]:
    """Combines runs made with different judges on the same scenes into one run folder `out`, as
    `sceneeval ensemble RUN... --out OUT` does (docs/judge.md, "Ensembles of judges"): every
    text-fidelity verdict is the majority of the runs' (a tie or no verdict: `None`, counted as
    unanswered), the scores recounted; geometry, views and matching are the first run's.
    `annotations` (the runs' annotation file) adds the summary's rows per difficulty.

    Returns a dict: `runs` (the runs' names, in vote order), `scenes`, `ties` (specs whose runs
    tied), `differences` (one dict per scene and geometry metric in which a run differs from
    the first: `scene`, `metric`, `run`, `detail`; each also a UserWarning) and `summary` (the
    summary written, as `evaluate` returns it).

    Raises ValueError for fewer than two runs, SceneEvalError when a run cannot be read, the
    runs differ in more than the judge (the message names the runs and what differs) or the
    folder cannot be written.
    """

def evaluate(
    scenes: PathLike,
    *,
    assets: Optional[Mapping[str, PathLike]],
    out: PathLike,
    annotations: Optional[PathLike] = None,
    plan: Optional[str] = None,
    preset: Optional[str] = None,
    metrics: Optional[Sequence[str]] = None,
    matching: Optional[PathLike] = None,
    relation_mapping: Optional[str] = None,
    time_budget_s: Optional[float] = None,
    vlm: Optional[Mapping[str, Any]] = None,
    force: bool = False,
    threads: Optional[int] = None,
    strict: bool = False,
    dry_run: bool = False,
) -> Dict[str, Any]:
    """Evaluates every `scene_<ID>.json` of the folder scenes as `sceneeval evaluate` does, writing the same files into out: `<scene>/eval.json` and `<scene>/timing.json` as each scene finishes, then summary.csv and summary.md.

    assets: as for load_scene. annotations: a SceneEval-500 annotation CSV (or JSON): the rows
    the text-fidelity metrics check, and rows per difficulty in the summary. plan: exactly what
    `sceneeval evaluate --plan` accepts: "geometry" (the default: the six geometry metrics),
    "full" (the paper's ten metrics, adding cnt, atr, oor, oar, which need annotations), a
    comma-separated metric list ("collision,cnt,oor") or the path of a plan file (JSON or
    TOML). preset: "default" or "reference" (every reference-parity switch), as --preset:
    the parameters start from it (it replaces a plan file's preset; a preset name given as
    plan=, the spelling of earlier versions, is read as preset= with a DeprecationWarning).
    metrics: run only these metrics (names or summary columns, e.g. "collision", "OOB", "cnt"),
    as --metrics. matching: "vlm", "labels" or a matching file or folder in
    the reference's obj_matching_result.json shape (`<folder>/<scene>/obj_matching_result.json`),
    as --matching; relation_mapping: "vlm" or "lexicon", as --relation-mapping. time_budget_s:
    seconds per scene, as --time-budget-s (a scene over it is recorded as failed; 0: no budget).
    vlm: the OpenAI-compatible endpoint the text-fidelity metrics ask, as the --vlm-* options: a
    dict with base_url and model (required), api_key_env (the variable holding the key, which
    must then be set; default OPENAI_API_KEY when set), cache (default out/vlm-cache),
    concurrency (4: requests in flight over the whole run, whatever the threads; halved on a 429
    and grown back), render_size (512, the object views shown), detail ("low"), temperature (0;
    None sends none, as OpenAI's reasoning models need), seed (42; None sends none), max_tokens,
    token_limit_field ("max_tokens" or "max_completion_tokens"), timeout_s (60: seconds per
    request attempt; time_budget_s bounds a scene's whole wait for the VLM), rpm and tpm (caps on
    requests and estimated tokens per minute; none by default). The dict is checked whatever the
    plan; VLM settings a plan without text-fidelity metrics does not use are reported with a
    UserWarning. Before the first scene evaluated, one small request checks the endpoint: an
    unreachable server or a refused key raises SceneEvalError at once. Without a VLM the
    text-fidelity metrics match objects by labels (or a matching file) and map relations with the
    lexicon (ATR is not judged), as the CLI does without one, and say so with a UserWarning and
    the run's note. A re-run into the same out reuses a scene's result while nothing it depends
    on changed (force=True evaluates every scene again). threads: worker threads (default one
    per core). strict=True fails each scene file that has keys the sceneState format does not
    have (a misspelt key is read as absent), as --strict; by default each is a warning. dry_run=True evaluates nothing, writes nothing and sends nothing: it returns what
    the run would ask the VLM (see below). Runs with the GIL released.

    With dry_run=True, returns scenes, evaluated (scenes the run would evaluate), reused,
    attributes_estimated (scenes whose attribute requests are estimated: one per ObjAttr entry,
    as their matching is not cached), failed ([scene, why] pairs), vlm (whether a VLM would be
    asked), tasks (per task: task, requests, cached, estimated, prompt_tokens: the estimated
    input tokens of the requests to send) and total (the same, summed), as
    `sceneeval evaluate --dry-run` prints them. Otherwise returns the run: out, scenes, evaluated, reused, failed, partial (scenes
    with status partial: some metrics could not be computed, the others kept), skipped (files
    that look like scenes but are not `scene_<ID>.json`), failures (scene, error, causes),
    incomplete (scene, metric, vlm: whether a VLM request failed, error, causes: each metric a
    partial scene could not compute), note (what the text-fidelity metrics ran with instead of
    a VLM, or None) and summary (the table of summary.csv as a dict). A scene that fails is
    recorded, not raised.
    Raises SceneEvalError when the folder, the annotations or the output cannot be used, and
    ValueError for a bad plan, preset, metric, assets mapping or vlm dict; the message starts
    with the keyword at fault (`plan: ...`, `vlm["detail"]: ...`). The keywords are the
    request's names (`sceneeval evaluate --print-request`); scenes_dir, time_budget and
    time_budget_seconds, and vlm["timeout"], their names in earlier versions, still work with a
    DeprecationWarning.
    """

def evaluation_request(
    scenes: PathLike,
    *,
    assets: Optional[Mapping[str, PathLike]],
    out: PathLike,
    annotations: Optional[PathLike] = None,
    plan: Optional[str] = None,
    preset: Optional[str] = None,
    metrics: Optional[Sequence[str]] = None,
    matching: Optional[PathLike] = None,
    relation_mapping: Optional[str] = None,
    time_budget_s: Optional[float] = None,
    vlm: Optional[Mapping[str, Any]] = None,
    force: bool = False,
    threads: Optional[int] = None,
    strict: bool = False,
    dry_run: bool = False,
) -> Dict[str, Any]:
    """The evaluation request evaluate() makes of the same arguments, as a dict: what
    `sceneeval evaluate --print-request` prints for the same options. Nothing is read or run.
    dry_run is accepted as evaluate() takes it; it is not part of the request.
    """

def agreement(
    sources: Sequence[PathLike],
    reference: Optional[Union[PathLike, Sequence[PathLike]]] = None,
    *,
    bootstrap: int = 1000,
    seed: int = 20261121,
) -> List[Dict[str, Any]]:
    """How far judges agree with people on the fidelity specs (`sceneeval agreement`,
    docs/judge.md).

    `sources`: run folders (each its VLM judge, named after the folder) and label files (one
    rater per annotator). `reference`: a label file or a list of them whose annotators'
    majority is the reference; `None` compares every pair of raters. `bootstrap`: resamples of
    each kappa's 95 % percentile interval (0: none); `seed`: the bootstrap's seed.

    Returns a list of dicts, one per rater pair and metric, with the keys of the CSV
    (`kind`, `a`, `b`, `metric`, `n`, `agreement`, `kappa`, `kappa_low`, `kappa_high`,
    `undefined`, `tt`, `tf`, `ft`, `ff`, `left_out_null`, `left_out_tie`, ...); a kappa that
    does not exist is `None` with the reason in `undefined`.

    Raises `SceneEvalError` for a file that cannot be read or a label that does not fit a run
    (the message names the file and line), `ValueError` for bad arguments.
    """
