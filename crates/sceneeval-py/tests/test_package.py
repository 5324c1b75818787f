"""The package's surface: the stubs list what the module exports, with the same docstrings."""

import ast
import inspect
from pathlib import Path

import sceneeval
from sceneeval import _sceneeval

STUB = Path(sceneeval.__file__).with_name("_sceneeval.pyi")


def words(text):
    return " ".join((text or "").split())


def is_bare_overload(node):
    """An @overload of a function whose documented overload comes first (the docstring is
    written once, on that one)."""
    overload = any(isinstance(d, ast.Name) and d.id == "overload" for d in node.decorator_list)
    return overload and ast.get_docstring(node) is None


def stub_items():
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not is_bare_overload(node):
            yield node.name, node
            if isinstance(node, ast.ClassDef):
                for member in node.body:
                    if isinstance(member, ast.FunctionDef) and not member.name.startswith("__"):
                        yield f"{node.name}.{member.name}", member


def test_stubs_and_runtime_docstrings_agree():
    names = []
    for name, node in stub_items():
        obj = _sceneeval
        for part in name.split("."):
            obj = getattr(obj, part)
        names.append(name)
        assert words(ast.get_docstring(node)) == words(inspect.getdoc(obj)), name
    assert {"relation", "relation_batch", "load_scene", "evaluate", "Scene", "Scene.plausibility"} <= set(names)
    exported = {n for n in dir(_sceneeval) if not n.startswith("_")}
    assert exported <= set(sceneeval.__all__)
    assert (Path(sceneeval.__file__).with_name("py.typed")).exists()


def test_the_fixed_signatures():
    sig = inspect.signature(sceneeval.relation)
    assert list(sig.parameters)[:3] == ["name", "target", "anchor"]
    assert sig.parameters["side"].kind is inspect.Parameter.KEYWORD_ONLY
    assert sig.parameters["reference"].default is False
    sig = inspect.signature(sceneeval.relation_batch)
    assert list(sig.parameters)[:3] == ["name", "targets", "anchors"]
    assert sig.parameters["grad"].kind is inspect.Parameter.KEYWORD_ONLY
    assert sig.parameters["grad"].default is False
    sig = inspect.signature(sceneeval.evaluate)
    assert [p for p in sig.parameters if sig.parameters[p].kind is inspect.Parameter.KEYWORD_ONLY][:4] == [
        "assets", "out", "annotations", "plan"
    ]


def test_importing_turns_off_mesas_device_select_layer_unless_set():
    # The layer made every successful render print "error: XDG_RUNTIME_DIR is invalid or not
    # set" where that variable is unset; a value the user set is kept.
    import os
    import subprocess
    import sys

    code = "import os, sceneeval; print(os.environ['NODEVICE_SELECT'])"
    env = {k: v for k, v in os.environ.items() if k != "NODEVICE_SELECT"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "1"
    env["NODEVICE_SELECT"] = "0"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "0"


def test_the_documented_vlm_defaults_are_the_rust_constants():
    # The defaults are written once, in Rust; the docstring quotes them and must not drift.
    doc = words(inspect.getdoc(sceneeval.evaluate))
    assert f"timeout_s ({sceneeval.DEFAULT_VLM_TIMEOUT_SECONDS:g}:" in doc
    assert f"concurrency ({sceneeval.DEFAULT_VLM_CONCURRENCY}:" in doc
    assert f"render_size ({sceneeval.DEFAULT_RENDER_SIZE}," in doc
