"""SceneEval in Rust: the 23 spatial-relation predicates, scenes, the plausibility metrics and
evaluation of generated 3D indoor scenes.

Boxes are ``(cx, cy, cz, hx, hy, hz, yaw)``: centre, half extents (metres) and yaw (radians
about +z; yaw 0 means the object's front faces world -y). World z is up. See ``help()`` of each
function, the type stubs, and the README's Python section.
"""

from ._sceneeval import (
    OBJECT_ARCHITECTURE_RELATIONS,
    OBJECT_OBJECT_RELATIONS,
    Scene,
    SceneEvalError,
    __version__,
    evaluate,
    evaluation_request,
    load_scene,
    relation,
    relation_batch,
    relation_names,
    relation_params,
)

__all__ = [
    "OBJECT_ARCHITECTURE_RELATIONS",
    "OBJECT_OBJECT_RELATIONS",
    "Scene",
    "SceneEvalError",
    "__version__",
    "evaluate",
    "evaluation_request",
    "load_scene",
    "relation",
    "relation_batch",
    "relation_names",
    "relation_params",
]
