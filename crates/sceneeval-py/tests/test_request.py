"""The two front ends build the same evaluation request from the same options:
`sceneeval evaluate --print-request` and `sceneeval.evaluation_request(...)`."""

import inspect
import json
import subprocess

import pytest

import sceneeval

# (CLI options, keyword arguments) that mean the same; every request has scenes, out and one
# asset folder.
CASES = [
    ([], {}),
    (["--plan", "full", "--annotations", "a.csv", "--preset", "reference"],
     {"plan": "full", "annotations": "a.csv", "preset": "reference"}),
    (["--plan", "collision,oob", "--metrics", "collision,COL_ob,cnt", "--time-budget-s", "30",
      "--matching", "labels", "--relation-mapping", "lexicon", "--force", "--threads", "2", "--strict"],
     {"plan": "collision,oob", "metrics": ["collision", "COL_ob", "cnt"], "time_budget_s": 30,
      "matching": "labels", "relation_mapping": "lexicon", "force": True, "threads": 2, "strict": True}),
    (["--plan", "full", "--annotations", "a.csv", "--vlm-base-url", "http://127.0.0.1:9/v1",
      "--vlm-model", "m", "--vlm-api-key-env", "MY_KEY", "--vlm-concurrency", "16", "--render-size", "256",
      "--vlm-cache", "cache", "--vlm-detail", "high", "--vlm-temperature", "none", "--vlm-seed", "7",
      "--vlm-max-tokens", "300", "--vlm-token-limit-field", "max_completion_tokens",
      "--vlm-timeout-s", "30", "--vlm-rpm", "500", "--vlm-tpm", "30000"],
     {"plan": "full", "annotations": "a.csv",
      "vlm": {"base_url": "http://127.0.0.1:9/v1", "model": "m", "api_key_env": "MY_KEY", "concurrency": 16,
              "render_size": 256, "cache": "cache", "detail": "high", "temperature": None, "seed": 7,
              "max_tokens": 300, "token_limit_field": "max_completion_tokens",
              "timeout_s": 30, "rpm": 500, "tpm": 30000}}),
]


@pytest.mark.parametrize("cli,kwargs", CASES)
def test_both_front_ends_build_the_same_request(sceneeval_bin, cli, kwargs):
    printed = subprocess.run(
        [str(sceneeval_bin), "evaluate", "scenes", "--out", "out", "--assets", "fixture=assets",
         "--print-request", *cli],
        check=True, capture_output=True, text=True,
    ).stdout
    from_cli = json.loads(printed)
    from_python = sceneeval.evaluation_request("scenes", out="out", assets={"fixture": "assets"}, **kwargs)
    assert from_python == from_cli
    # The request is the options, not their consequences: nothing is resolved or read.
    assert from_cli["scenes"] == "scenes" and from_cli["assets"] == ["fixture=assets"]


def test_request_errors_name_the_keyword(tmp_path):
    (tmp_path / "scene_1.json").write_text("{}")
    csv = tmp_path / "a.csv"
    csv.write_text("ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n1,easy,A room.,,,,\n")
    with pytest.raises(ValueError, match=r'^vlm\["render_size"\]: 20000 pixels is not from 16 to 4096'):
        sceneeval.evaluate(tmp_path, assets={}, out=tmp_path / "o", plan="full", annotations=csv,
                           vlm={"base_url": "http://127.0.0.1:9/v1", "model": "m", "render_size": 20000})
    with pytest.raises(ValueError, match=r'^plan: "colision" is not geometry, full, a plan file or a metric list: '
                                         r'.*did you mean "collision"'):
        sceneeval.evaluate(tmp_path, assets={}, out=tmp_path / "o", plan="colision")


def test_the_keywords_are_the_request_names():
    # One table: every keyword of evaluate() is a field of the request it makes, by that name.
    request = sceneeval.evaluation_request("scenes", out="out", assets={})
    fields = (set(request) - {"plan", "shard", "diagnostics"}) | set(request["plan"])
    for function in (sceneeval.evaluate, sceneeval.evaluation_request):
        params = inspect.signature(function).parameters
        keywords = {n for n, p in params.items() if p.kind is not inspect.Parameter.VAR_KEYWORD} - {"dry_run"}
        assert keywords == fields, function.__name__


def test_the_old_keyword_names_warn_and_still_work():
    new = sceneeval.evaluation_request("scenes", out="out", assets={}, time_budget_s=30)
    assert new["plan"]["time_budget_s"] == 30
    with pytest.warns(DeprecationWarning, match=r"^scenes_dir= is deprecated: pass scenes= "):
        old = sceneeval.evaluation_request(scenes_dir="scenes", out="out", assets={}, time_budget_s=30)
    assert old == new
    for name in ("time_budget", "time_budget_seconds"):
        with pytest.warns(DeprecationWarning, match=rf"^{name}= is deprecated: pass time_budget_s= "):
            old = sceneeval.evaluation_request("scenes", out="out", assets={}, **{name: 30})
        assert old == new
        with pytest.warns(DeprecationWarning), pytest.raises(TypeError, match=rf"time_budget_s= and its old name {name}="):
            sceneeval.evaluation_request("scenes", out="out", assets={}, time_budget_s=3, **{name: 3})
    with pytest.warns(DeprecationWarning), pytest.raises(TypeError, match=r"two old names of time_budget_s="):
        sceneeval.evaluation_request("scenes", out="out", assets={}, time_budget=3, time_budget_seconds=3)
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'time_budgets'"):
        sceneeval.evaluation_request("scenes", out="out", assets={}, time_budgets=3)
    with pytest.raises(TypeError, match=r"missing 1 required argument: 'scenes'"):
        sceneeval.evaluation_request(out="out", assets={})


def test_the_old_vlm_timeout_key_warns_and_still_works():
    vlm = {"base_url": "http://127.0.0.1:9/v1", "model": "m"}
    new = sceneeval.evaluation_request("scenes", out="out", assets={}, vlm={**vlm, "timeout_s": 30})
    assert new["vlm"]["timeout_s"] == 30 and "timeout" not in new["vlm"]
    with pytest.warns(DeprecationWarning, match=r'^vlm\["timeout"\] is deprecated: use vlm\["timeout_s"\] '):
        old = sceneeval.evaluation_request("scenes", out="out", assets={}, vlm={**vlm, "timeout": 30})
    assert old == new
    with pytest.raises(TypeError, match=r'vlm has "timeout_s" and its old name "timeout"'):
        sceneeval.evaluation_request("scenes", out="out", assets={}, vlm={**vlm, "timeout": 3, "timeout_s": 3})
