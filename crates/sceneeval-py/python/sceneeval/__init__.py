"""SceneEval in Rust: the 23 spatial-relation predicates, scenes, the plausibility metrics and
evaluation of generated 3D indoor scenes.

Boxes are ``(cx, cy, cz, hx, hy, hz, yaw)``: centre, half extents (metres) and yaw (radians
about +z; yaw 0 means the object's front faces world -y). World z is up. See ``help()`` of each
function, the type stubs, and the README's Python section.
"""

import os as _os
import sys as _sys

# Mesa's device-select Vulkan layer asks libwayland for a display while the renderer picks its
# adapter, and libwayland prints "error: XDG_RUNTIME_DIR is invalid or not set" where that
# variable is unset (containers, CI, services), on renders that succeed. The renders are
# headless and wgpu picks the adapter itself: turn the layer off unless the environment says
# otherwise (the `sceneeval` command does the same).
_os.environ.setdefault("NODEVICE_SELECT", "1")

from ._sceneeval import (  # noqa: E402
    DEFAULT_RENDER_SIZE,
    DEFAULT_VLM_CONCURRENCY,
    DEFAULT_VLM_TIMEOUT_SECONDS,
    OBJECT_ARCHITECTURE_RELATIONS,
    OBJECT_OBJECT_RELATIONS,
    Scene,
    SceneEvalError,
    __version__,
    agreement,
    compare,
    ensemble,
    evaluate,
    evaluation_request,
    load_scene,
    relation,
    relation_batch,
    relation_names,
    relation_params,
    stats,
)

# `import sceneeval.stats` and `from sceneeval.stats import wilcoxon` find the submodule of the
# extension (which is not a package of its own).
stats.__name__ = __name__ + ".stats"
_sys.modules[stats.__name__] = stats

__all__ = [
    "DEFAULT_RENDER_SIZE",
    "DEFAULT_VLM_CONCURRENCY",
    "DEFAULT_VLM_TIMEOUT_SECONDS",
    "OBJECT_ARCHITECTURE_RELATIONS",
    "OBJECT_OBJECT_RELATIONS",
    "Scene",
    "SceneEvalError",
    "__version__",
    "agreement",
    "compare",
    "ensemble",
    "evaluate",
    "evaluation_request",
    "load_scene",
    "relation",
    "relation_batch",
    "relation_names",
    "relation_params",
    "stats",
]
