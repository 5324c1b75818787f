"""sceneeval.evaluate(vlm=...) asks an OpenAI-compatible endpoint as `sceneeval evaluate --vlm-*`
does: against a mock server started here on 127.0.0.1, the same requests and the same eval.json
as the CLI."""

import base64
import json
import shutil
import subprocess
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pytest

import sceneeval
from conftest import FIXTURES

# Scene 8 (fixture): wardrobe, bed, nightstand, ceiling lamp, in this order.
CSV = (
    "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n"
    '8,easy,A small bedroom.,"eq,1,wardrobe; eq,1,bed; eq,1,nightstand; eq,1,ceiling_lamp; eq,0,tv; eq,2,chair",'
    '"eq,1,wardrobe,tall","eq,1,next_to,0,bed,nightstand; eq,1,in_harmony_with,0,bed,wardrobe",'
    '"eq,1,against,bed,wall; eq,1,next_to,wardrobe,door"\n'
)


def pictured_category(outs, png):
    """The category of the object whose front view a run wrote under one of `outs` with the
    bytes `png` (`<out>/<scene>/views/front_idx<k>_fixture.<category>.png`), or None. A scene's
    questions are asked together: a matching request is recognised by its image, not its order."""
    for out in outs:
        for view in out.glob("*/views/front_*.png"):
            if view.read_bytes() == png:
                return view.stem.rsplit("fixture.", 1)[-1]
    return None


def answer(task, user_text, pictured):
    """What the model answers: the nightstand is not recognised, the wardrobe is tall,
    "in_harmony_with" is not spatial, every object is used from the front. `pictured` is the
    category of the object a matching request shows."""
    if task == "obj_matching":
        category = pictured
        assert category is not None, "a matching request whose image is no front view a run wrote"
        matched = category != "nightstand"
        return {"provided_categories": [], "matched": matched, "matched_category": category if matched else "",
                "actual_category": category, "reason": f"looks like a {category}"}
    if task == "obj_attribute":
        return {"category": "wardrobe", "num_instances": 1,
                "assessments": [{"instance": 0, "attribute": "tall", "satisfied": True, "reason": "2 m"}]}
    if task == "obj_functional_sides":
        ids = [part.split('"', 1)[0] for part in user_text.split('obj_id: "')[1:]]
        return {"assessments": [{"obj_id": i, "obj_description": "", "functional_sides": ["front"],
                                 "reason": "used from the front"} for i in ids]}
    if task == "obj_support_type":
        return {"support_type": "ground", "reason": "on the floor"}
    if task == "endpoint_check":
        return {"colour": "red", "reason": "a red square"}
    if task == "obj_relationship_mapping":
        return {"assessments": [{"key": "1", "relationship": "in_harmony_with", "anchor_object": "bed",
                                 "other_objects": ["wardrobe"], "other_object_counts": [1],
                                 "relationship_types": None, "sides": [], "reason": "not spatial"}]}
    raise AssertionError(f"unexpected task {task}")


class MockServer:
    """A chat-completions endpoint on 127.0.0.1 answering with `answer`; records what it got.
    `views` are the output folders of the runs it serves (their front views name the objects)."""

    def __init__(self, views=()):
        self.requests = []  # (headers with lower-case names, body)
        self.lock = threading.Lock()
        server = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self):
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                task = body["response_format"]["json_schema"]["name"]
                content_parts = body["messages"][1]["content"]
                text = content_parts[0]["text"]
                images = [p["image_url"]["url"].split("base64,", 1)[1] for p in content_parts[1:]]
                pictured = pictured_category(views, base64.b64decode(images[0])) if images else None
                with server.lock:
                    server.requests.append(({k.lower(): v for k, v in self.headers.items()}, body))
                content = json.dumps(answer(task, text, pictured))
                reply = json.dumps({
                    "choices": [{"index": 0, "message": {"role": "assistant", "content": content},
                                 "finish_reason": "stop"}],
                    "usage": {"prompt_tokens": 100, "completion_tokens": 20, "total_tokens": 120},
                }).encode()
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(reply)))
                self.end_headers()
                self.wfile.write(reply)

            def log_message(self, *args):
                pass

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)
        self.thread.start()
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"

    def close(self):
        self.httpd.shutdown()
        self.httpd.server_close()


@pytest.fixture
def server():
    s = MockServer()
    yield s
    s.close()


@pytest.fixture
def scene_8(tmp_path):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    shutil.copy(FIXTURES / "scenes" / "scene_8.json", scenes / "scene_8.json")
    csv = tmp_path / "annotations.csv"
    csv.write_text(CSV)
    return scenes, csv


def test_evaluate_asks_the_vlm_as_the_cli_does(sceneeval_bin, scene_8, tmp_path, monkeypatch):
    scenes, csv = scene_8
    monkeypatch.setenv("MY_TEST_VLM_KEY", "sk-python-test")
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    cli_server, py_server = MockServer([tmp_path / "cli"]), MockServer([tmp_path / "py"])
    try:
        subprocess.run(
            [str(sceneeval_bin), "evaluate", str(scenes), "--assets", f"fixture={FIXTURES / 'assets'}",
             "--out", str(tmp_path / "cli"), "--annotations", str(csv), "--plan", "full", "--no-progress",
             "--relation-mapping", "lexicon", "--threads", "1", "--render-size", "64",
             "--vlm-base-url", cli_server.url, "--vlm-model", "test-model", "--vlm-api-key-env", "MY_TEST_VLM_KEY",
             "--vlm-temperature", "none", "--vlm-seed", "7"],
            check=True, capture_output=True,
        )
        run = sceneeval.evaluate(
            scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "py", annotations=csv, plan="full",
            relation_mapping="lexicon", threads=1,
            vlm={"base_url": py_server.url, "model": "test-model", "api_key_env": "MY_TEST_VLM_KEY",
                 "temperature": None, "seed": 7, "render_size": 64},
        )
    finally:
        cli_server.close()
        py_server.close()
    assert (run["evaluated"], run["failed"], run["note"]) == (1, 0, None)
    py_record = (tmp_path / "py" / "scene_8" / "eval.json").read_bytes()
    assert py_record == (tmp_path / "cli" / "scene_8" / "eval.json").read_bytes()
    # The endpoint check, then functional sides, four matchings, one attribute, one relation
    # mapping; the settings given.
    assert len(py_server.requests) == len(cli_server.requests) == 8
    assert py_server.requests[0][1]["response_format"]["json_schema"]["name"] == "endpoint_check"
    for headers, body in py_server.requests:
        assert headers["authorization"] == "Bearer sk-python-test"
        assert "temperature" not in body and body["seed"] == 7 and body["model"] == "test-model"
    summary = json.loads(py_record)["report"]["summary"]
    assert [summary[m] for m in ("cnt", "atr", "oor", "oar")] == [pytest.approx(4 / 6), 1.0, 0.0, 1.0]
    # The answers are cached under out/vlm-cache: a forced re-run asks nothing.
    again = MockServer([tmp_path / "py"])
    try:
        sceneeval.evaluate(
            scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "py", annotations=csv, plan="full",
            relation_mapping="lexicon", force=True,
            vlm={"base_url": again.url, "model": "test-model", "api_key_env": "MY_TEST_VLM_KEY",
                 "temperature": None, "seed": 7, "render_size": 64},
        )
    finally:
        again.close()
    # Only the endpoint check made before the first scene.
    assert [b["response_format"]["json_schema"]["name"] for _, b in again.requests] == ["endpoint_check"]
    # The record does not depend on where the answers came from: byte for byte the first one.
    assert (tmp_path / "py" / "scene_8" / "eval.json").read_bytes() == py_record
    report = json.loads(py_record)["report"]
    assert report["fidelity"]["vlm_usage"]["requests"] == 7


def test_bad_vlm_settings_raise_before_any_request(scene_8, tmp_path, server, monkeypatch):
    scenes, csv = scene_8
    monkeypatch.delenv("SCENEEVAL_UNSET_KEY_VAR", raising=False)

    def evaluate(vlm):
        return sceneeval.evaluate(scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "out",
                                  annotations=csv, plan="full", vlm=vlm)

    base = {"base_url": server.url, "model": "m"}
    for vlm, message in [
        ({"base_url": server.url}, "vlm: missing field `model`"),
        ({**base, "temperatur": 0.5}, "vlm: unknown field `temperatur`"),
        ({**base, "temperature": 3.0}, r'^vlm\["temperature"\]: 3 is not from 0 to 2 \(or none\)'),
        ({**base, "detail": "medium"}, r'vlm\["detail"\]: image detail "medium" is not one of low, high, auto'),
        ({**base, "token_limit_field": "max_output_tokens"}, r'vlm\["token_limit_field"\]'),
        ({**base, "api_key_env": "SCENEEVAL_UNSET_KEY_VAR"}, r'^vlm\["api_key_env"\]: no API key: .*SCENEEVAL_UNSET_KEY_VAR: is not set or empty'),
        ({**base, "base_url": "localhost:9"}, r'^vlm\["base_url"\]: cannot set up the VLM client: .*base URL'),
        ({**base, "cache": 3}, r'vlm\["cache"\] must be a path'),
        ({**base, "timeout_s": 0}, r'^vlm\["timeout_s"\]: 0 is not a number of seconds above 0'),
        ({**base, "rpm": 0}, r'^vlm\["rpm"\]: must be at least 1 request per minute'),
        ({**base, "tpm": 0}, r'^vlm\["tpm"\]: must be at least 1 token per minute'),
    ]:
        with pytest.raises(ValueError, match=message):
            evaluate(vlm)
    assert server.requests == []


def test_vlm_settings_are_checked_and_reported_unused_whatever_the_plan(scene_8, tmp_path, server):
    scenes, _ = scene_8
    vlm = {"base_url": server.url, "model": "m"}
    with pytest.warns(UserWarning, match="the plan runs no text-fidelity metric .* the VLM options are not used"):
        run = sceneeval.evaluate(scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "o",
                                 plan="collision", vlm=vlm)
    assert run["evaluated"] == 1
    with pytest.raises(ValueError, match=r'^vlm\["detail"\]'):
        sceneeval.evaluate(scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "o",
                           plan="collision", vlm={**vlm, "detail": "medium"})
    assert server.requests == []


def test_a_dry_run_sends_nothing(scene_8, tmp_path, server):
    scenes, csv = scene_8
    dry = sceneeval.evaluate(
        scenes, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "o", annotations=csv, plan="full",
        relation_mapping="lexicon", dry_run=True,
        vlm={"base_url": server.url, "model": "test-model", "render_size": 64},
    )
    assert server.requests == []
    assert not (tmp_path / "o" / "scene_8").exists()
    assert (dry["scenes"], dry["evaluated"], dry["reused"]) == (1, 1, 0)
    tasks = {t["task"]: t for t in dry["tasks"]}
    # Scene 8's four objects; one ObjAttr entry, estimated (the matching is not cached).
    assert (tasks["obj_matching"]["requests"], tasks["obj_matching"]["cached"]) == (4, 0)
    assert (tasks["obj_attribute"]["requests"], tasks["obj_attribute"]["estimated"]) == (1, 1)
    assert dry["total"]["prompt_tokens"] > 0


def test_settle_asks_the_vlm_for_the_support_types_the_scene_does_not_state(tmp_path, server, monkeypatch):
    # Fixture scene 7 (sofa, coffee table, floor lamp, plant, painting on a wall) without its
    # stated support types. The category tables call the painting a wall object, welded under
    # the default weld mode "architectural"; the model answers "ground" for every object, so
    # settled with the VLM the painting is free and falls.
    state = json.loads((FIXTURES / "scenes" / "scene_7.json").read_text())
    for o in state["scene"]["object"]:
        del o["supportType"]
    path = tmp_path / "scene_7.json"
    path.write_text(json.dumps(state))
    assets = {"fixture": FIXTURES / "assets"}
    scene = sceneeval.load_scene(path, assets=assets)
    painting = "idx4_fixture.painting"
    by_tables = {o["id"]: o for o in scene.stability()["objects"]}
    assert by_tables[painting]["weld_reason"] == "wall" and by_tables[painting]["stable"]
    assert "placement" not in scene.stability()

    monkeypatch.setenv("MY_SETTLE_KEY", "sk-settle-secret")
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    cache = tmp_path / "answers"
    vlm = {"base_url": server.url, "model": "test-model", "api_key_env": "MY_SETTLE_KEY", "render_size": 64,
           "cache": cache}
    settled, report = scene.settle(vlm=vlm, assets=assets)
    asked = [b for _, b in server.requests if b["response_format"]["json_schema"]["name"] == "obj_support_type"]
    assert len(asked) == 5, "one question per object without a stated support type"
    assert all(h["authorization"] == "Bearer sk-settle-secret" for h, _ in server.requests)
    support = {p["object"]: p["support_type"] for p in report["placement"]}
    assert support[painting] == {"value": "ground", "source": "vlm", "reason": "on the floor"}
    objects = {o["id"]: o for o in report["objects"]}
    assert objects[painting]["welded"] is False and objects[painting]["stable"] is False
    # It fell: the settled scene has it lower by more than its displacement limit; the scene
    # itself is not moved.
    assert settled.boxes()[4, 2] < scene.boxes()[4, 2] - 0.3
    assert objects[painting]["displacement_m"] > 0.3
    # The answers are cached where vlm["cache"] says, and the key is in no file.
    files = [f for f in cache.rglob("*") if f.is_file()]
    assert files
    for f in files:
        assert b"sk-settle-secret" not in f.read_bytes(), f

    # stability(vlm=...) gives the same report, its answers from the cache.
    again = MockServer()
    try:
        same = scene.stability(vlm={**vlm, "base_url": again.url}, assets=assets)
    finally:
        again.close()
    assert [b for _, b in again.requests if b["response_format"]["json_schema"]["name"] == "obj_support_type"] == []
    assert same == report
    with pytest.raises(ValueError, match=r'^vlm: missing field `model`'):
        scene.settle(vlm={"base_url": server.url})
