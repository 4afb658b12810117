"""extremal.batch on a local Dask cluster of two worker processes: the files it writes are the
files `extremal report SCENES... -o OUT` writes for the same scenes (one scene, several, stems
that clash; CSV byte for byte, JSON equal but for the step times), one task per scene or per body pair, the scene
files read from their paths or shipped to workers that cannot see them."""

import json
import os
import shutil
import subprocess
import sys

import pytest
from distributed import Client, LocalCluster

import extremal
from extremal import batch
from scenes import write_scenes, write_small


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None,
                           local_directory=str(tmp_path_factory.mktemp("dask")))
    c = Client(cluster)
    pids = c.run(os.getpid)
    assert len(pids) == 2 and os.getpid() not in pids.values()  # two worker processes
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def scenes(tmp_path_factory, shared_data):
    return write_scenes(tmp_path_factory.mktemp("scenes"), shared_data)


def command(cli, scenes, output, *extra):
    code, out, err = cli("report", *scenes, "-o", output, *extra)
    assert code == 0, err
    return out


TIMING = ("step_time_us", "audit_time_us")  # the timing fields: they differ from run to run


def without_timing(report):
    """A JSON report but for its timing fields (the scene's and each pair's step_time_us and
    audit_time_us), which must be there with their four statistics."""
    report = dict(report)
    for key in TIMING:
        assert set(report.pop(key)) == {"mean", "median", "p99", "max"}
    summary = []
    for s in report["summary"]:
        s = dict(s)
        for key in TIMING:
            assert set(s.pop(key)) == {"mean", "median", "p99", "max"}
        summary.append(s)
    report["summary"] = summary
    return report


def without_timing_lines(text):
    """A printed summary but for its step time lines."""
    return "".join(line for line in text.splitlines(True) if "step time" not in line)


def assert_same_files(ours, theirs):
    assert [os.path.basename(p) for p in ours] == [os.path.basename(p) for p in theirs]
    for a, b in zip(ours, theirs):
        if a.endswith(".json"):
            with open(a) as fa, open(b) as fb:
                assert without_timing(json.load(fa)) == without_timing(json.load(fb)), a
        else:
            with open(a, "rb") as fa, open(b, "rb") as fb:
                assert fa.read() == fb.read(), a


def expected_files(folder, stem, ext, tags):
    return [str(folder / f"{stem}.{tag}.{ext}") for tag in tags]


def test_several_scenes_write_the_commands_csv(client, scenes, cli, tmp_path):
    assert len(scenes) >= 8
    (tmp_path / "batch").mkdir()
    ours = batch.run(scenes, tmp_path / "batch" / "report.csv", client)
    tags = [p.stem for p in scenes]
    assert ours == expected_files(tmp_path / "batch", "report", "csv", tags)
    (tmp_path / "cli").mkdir()
    command(cli, scenes, tmp_path / "cli" / "report.csv", "--quiet")
    assert_same_files(ours, expected_files(tmp_path / "cli", "report", "csv", tags))


def test_a_task_per_pair_writes_the_same_json(client, scenes, cli, tmp_path):
    (tmp_path / "cli").mkdir()
    command(cli, scenes, tmp_path / "cli" / "r.json", "--quiet")
    ours = batch.run(scenes, tmp_path / "r.json", client, split="pair", threads=2)
    assert_same_files(ours, expected_files(tmp_path / "cli", "r", "json", [p.stem for p in scenes]))
    three = json.loads(open(ours[[p.stem for p in scenes].index("three")]).read())
    assert len(three["pairs"]) == 3 and len(three["summary"]) == 3


def test_one_scene_writes_the_output_itself(client, scenes, cli, tmp_path):
    three = [p for p in scenes if p.stem == "three"]
    for split in ("scene", "pair"):
        ours = batch.run(three, tmp_path / f"{split}.csv", client, split=split)
        assert ours == [str(tmp_path / f"{split}.csv")]
    command(cli, three, tmp_path / "cli.csv", "--quiet")
    for split in ("scene", "pair"):
        with open(tmp_path / f"{split}.csv", "rb") as a, open(tmp_path / "cli.csv", "rb") as b:
            assert a.read() == b.read()


def test_stems_that_clash_are_numbered(client, scenes, cli, tmp_path):
    clashing = [write_small(tmp_path / "one" / "a.json", 3.0), write_small(tmp_path / "two" / "a.json", 4.0),
                scenes[0]]
    (tmp_path / "out").mkdir()
    ours = batch.run(clashing, tmp_path / "out" / "report.json", client)
    tags = ["1-a", "2-a", f"3-{scenes[0].stem}"]
    assert ours == expected_files(tmp_path / "out", "report", "json", tags)
    (tmp_path / "cli").mkdir()
    command(cli, clashing, tmp_path / "cli" / "report.json", "--quiet")
    assert_same_files(ours, expected_files(tmp_path / "cli", "report", "json", tags))
    # The two a.json scenes differ: each file holds its own scene.
    assert json.load(open(ours[0]))["rows"] != json.load(open(ours[1]))["rows"]


def test_shipped_scenes_run_where_their_files_are_not(client, shared_data, cli, tmp_path):
    # Scenes with STEP parts named relatively and absolutely and a pose table, packed here;
    # then their folder is moved away, so the workers can only read what was shipped.
    folder = tmp_path / "project"
    scenes = write_scenes(folder, shared_data, copy_parts=True)
    picked = [p for p in scenes if p.stem in ("box_ball", "table", "two_solids", "spheres")]
    (tmp_path / "cli").mkdir()
    command(cli, picked, tmp_path / "cli" / "report.csv", "--quiet")
    command(cli, picked, tmp_path / "cli" / "report.json", "--quiet")
    shipped = [batch.ship(p) for p in picked]
    assert any(s.tables for s in shipped) and sum(len(s.files) for s in shipped) >= 3
    shutil.move(str(folder), str(tmp_path / "elsewhere"))
    assert not folder.exists()
    tags = [p.stem for p in picked]
    for ext in ("csv", "json"):
        ours = batch.run(shipped, tmp_path / f"report.{ext}", client, split="pair")
        assert_same_files(ours, expected_files(tmp_path / "cli", "report", ext, tags))
    # The JSON reports still name the scenes and parts by the paths they were given.
    box = json.load(open(tmp_path / "report.box_ball.json"))
    assert box["scene"] == str(folder / "box_ball.json")
    assert box["bodies"][0]["file"] == str(folder / "parts" / "pr2ct.stp")


def test_paths_shipped_by_run(client, scenes, cli, tmp_path):
    picked = [p for p in scenes if p.stem in ("table", "box_ball")]
    ours = batch.run(picked, tmp_path / "r.csv", client, ship=True)
    (tmp_path / "cli").mkdir()
    command(cli, picked, tmp_path / "cli" / "r.csv", "--quiet")
    assert_same_files(ours, expected_files(tmp_path / "cli", "r", "csv", [p.stem for p in picked]))


def test_a_bad_scene_stops_the_batch_before_any_task(client, scenes, cli, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"time": {"end": 1, "step": 0.1},
                               "bodies": [{"name": "A", "shape": {"type": "sphere", "radius": 1}},
                                          {"name": "B", "shape": {"type": "sphere", "radius": -1}}]}))
    with pytest.raises(extremal.InvalidInput, match=r"bad\.json: bodies\[1\]\.shape\.radius") as e:
        batch.run([scenes[0], bad], tmp_path / "out.csv", client)
    assert not list(tmp_path.glob("out*"))  # nothing written, not even the good scene's
    code, _, err = cli("report", scenes[0], bad, "-o", tmp_path / "cli.csv")
    assert code == 1 and err.strip() == "extremal report: " + str(e.value)
    with pytest.raises(extremal.InvalidInput, match=r"^-o out\.txt: expected a file name ending"):
        batch.run(scenes, "out.txt", client)


def module_run(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "extremal.batch", *map(str, args)],
                          capture_output=True, text=True, timeout=600, **kwargs)


def test_the_command_on_a_running_scheduler(client, scenes, cli, tmp_path):
    picked = [p for p in scenes if p.stem in ("ellipsoids", "farther", "three")]
    p = module_run(*picked, "-o", tmp_path / "r.csv", "--scheduler", client.scheduler.address)
    assert p.returncode == 0, p.stderr
    (tmp_path / "cli").mkdir()
    summaries = command(cli, picked, tmp_path / "cli" / "r.csv")
    tags = [s.stem for s in picked]
    assert_same_files(expected_files(tmp_path, "r", "csv", tags),
                      expected_files(tmp_path / "cli", "r", "csv", tags))
    # The same summaries the command prints, but for the files' folders and the step times.
    assert without_timing_lines(p.stdout) == without_timing_lines(
        summaries.replace(str(tmp_path / "cli") + os.sep, str(tmp_path) + os.sep))
    assert "minimum clearance" in p.stdout
    assert p.stdout.count("step time") == summaries.count("step time") > 0


def test_the_command_starts_its_own_cluster(scenes, cli, tmp_path):
    picked = [p for p in scenes if p.stem in ("spheres", "keyframes")]
    p = module_run(*picked, "-o", tmp_path / "r.json", "--workers", 2, "--quiet", "--ship")
    assert p.returncode == 0, p.stderr
    assert p.stdout == ""
    (tmp_path / "cli").mkdir()
    command(cli, picked, tmp_path / "cli" / "r.json", "--quiet")
    tags = [s.stem for s in picked]
    assert_same_files(expected_files(tmp_path, "r", "json", tags),
                      expected_files(tmp_path / "cli", "r", "json", tags))


def test_the_commands_exit_codes(tmp_path):
    usage = module_run(tmp_path / "a.json")  # no -o
    assert usage.returncode == 2 and "-o" in usage.stderr
    missing = module_run(tmp_path / "none.json", "-o", tmp_path / "r.csv", "--workers", 1)
    assert missing.returncode == 1
    assert missing.stderr.strip() == f"extremal.batch: {tmp_path / 'none.json'}: cannot open the scene file"
    nobody = module_run(tmp_path / "none.json", "-o", tmp_path / "r.csv", "--scheduler",
                        "tcp://127.0.0.1:9", "--connect-timeout", 2)
    assert nobody.returncode == 1 and "--scheduler tcp://127.0.0.1:9: cannot connect" in nobody.stderr


def test_import_extremal_does_not_import_dask():
    p = subprocess.run([sys.executable, "-c", "import sys, extremal; print('dask' in sys.modules, "
                        "'distributed' in sys.modules)"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["False", "False"]
