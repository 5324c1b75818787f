"""The two front ends build the same evaluation request from the same options:
`sceneeval evaluate --print-request` and `sceneeval.evaluation_request(...)`."""

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
    (["--plan", "collision,oob", "--metrics", "collision,COL_ob,cnt", "--time-budget", "30",
      "--matching", "labels", "--relation-mapping", "lexicon", "--force", "--threads", "2", "--strict"],
     {"plan": "collision,oob", "metrics": ["collision", "COL_ob", "cnt"], "time_budget": 30,
      "matching": "labels", "relation_mapping": "lexicon", "force": True, "threads": 2, "strict": True}),
    (["--plan", "full", "--annotations", "a.csv", "--vlm-base-url", "http://127.0.0.1:9/v1",
      "--vlm-model", "m", "--vlm-api-key-env", "MY_KEY", "--vlm-concurrency", "16", "--render-size", "256",
      "--vlm-cache", "cache", "--vlm-detail", "high", "--vlm-temperature", "none", "--vlm-seed", "7",
      "--vlm-max-tokens", "300", "--vlm-token-limit-field", "max_completion_tokens",
      "--vlm-timeout", "30", "--vlm-rpm", "500", "--vlm-tpm", "30000"],
     {"plan": "full", "annotations": "a.csv",
      "vlm": {"base_url": "http://127.0.0.1:9/v1", "model": "m", "api_key_env": "MY_KEY", "concurrency": 16,
              "render_size": 256, "cache": "cache", "detail": "high", "temperature": None, "seed": 7,
              "max_tokens": 300, "token_limit_field": "max_completion_tokens",
              "timeout": 30, "rpm": 500, "tpm": 30000}}),
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
