"""rocking.ida: the rows of `rocking ida`, and Ctrl-C stops it."""
import csv
import json
import pathlib
import os
import signal
import threading
import time

import numpy as np
import pytest

import rocking


def test_ida_rows_equal_the_programs_csv(cli, elcentro, tmp_path):
    out = tmp_path / "ida"
    r = cli.run("ida", "--record", elcentro, "--scales", "1,2", "--variants", "damper,no-damper",
                "--out", out, "--threads", "2", "--formats", "png")
    assert r.returncode == 0, r.stderr
    with open(out / "ida.csv") as f:
        rows = list(csv.DictReader(f))
    study = rocking.ida(None, [str(elcentro)], levels=[1, 2], variants=["damper", "no-damper"], threads=2)
    assert len(study.rows) == len(rows) == 4
    for mine, theirs in zip(study.rows, rows):
        assert mine["variant"] == theirs["variant"]
        assert mine["level"] == float(theirs["level"])
        for key in ("delta_t", "delta_e", "theta_over_alpha", "base_moment"):
            assert mine[key] == pytest.approx(float(theirs[key]), rel=1e-8), key  # the CSV's 9 digits
    fractiles = study.fractiles("theta_over_alpha", "no-damper")
    assert [f["level"] for f in fractiles] == [1, 2]
    # One record: its own peak, as the files hold it (9 digits, as the program's summary).
    assert fractiles[0]["p50"] == pytest.approx(study.rows[1]["theta_over_alpha"], rel=1e-8)
    assert fractiles[0]["p50"] == float(f"{study.rows[1]['theta_over_alpha']:.9g}")


def test_ctrl_c_stops_an_ida(elcentro):
    # 300,000 runs: hours of work, far beyond ctest's 300 s timeout, so the
    # call returns only because the signal stopped it. How soon it stops is a
    # measurement, not a test: bench/python_bench.py prints it.
    levels = [0.01 * k for k in range(1, 100001)]
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        rocking.ida(None, [str(elcentro)], levels=levels, threads=2)
    timer.cancel()


def test_ida_refuses_bad_arguments_with_value_error(elcentro):
    with pytest.raises(ValueError, match="unknown variant 'sideways'"):
        rocking.ida(None, [str(elcentro)], levels=[1], variants=["sideways"])
    with pytest.raises(ValueError, match="level -1: must be positive"):
        rocking.ida(None, [str(elcentro)], levels=[-1])
    with pytest.raises(ValueError, match="unknown quantity"):
        rocking.ida(None, [str(elcentro)], levels=[1], variants=["damper"]).fractiles("nope")


def test_ctrl_c_after_a_call_is_pythons_again_and_calls_from_threads_run(elcentro):
    rocking.simulate(record=str(elcentro), history=False)
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1)  # the interrupt lands here, raised by Python's own handler
    results = []
    worker = threading.Thread(target=lambda: results.append(rocking.simulate(record=str(elcentro), history=False)))
    worker.start()
    worker.join()
    assert results[0].peaks == rocking.simulate(record=str(elcentro), history=False).peaks


def test_fragility_equals_the_programs_summary(cli, records, tmp_path):
    files = [records / "elcentro_1940_ns.at2", records / "chichi1999_chy028_n.at2"]
    out = tmp_path / "ida"
    r = cli.run("ida", "--record", *files, "--scales", "0.5,1,2", "--variants", "damper",
                "--limit", "theta_over_alpha=0.01", "--out", out, "--no-plot")
    assert r.returncode == 0, r.stderr
    theirs = json.loads((out / "summary.json").read_text())["variants"][0]["fragility"]
    study = rocking.ida(None, [str(f) for f in files], levels=[0.5, 1, 2], variants=["damper"],
                        limits=["theta_over_alpha=0.01"])
    assert study.limits == ["overturning", "theta_over_alpha>=0.01"]
    for limit, expected in zip(study.limits, theirs):
        mine = study.fragility(limit, "damper")
        assert mine["limit"] == expected["limit"]
        assert [(pathlib.Path(c["record"]).name, c["level"], c["reached"]) for c in mine["capacities"]] == \
            [(c["record"], c["level"], c["reached"]) for c in expected["capacities"]]
        assert mine["stripes"] == expected["stripes"]
        for fit in ("capacity_fit", "stripes_fit"):
            assert mine[fit]["fitted"] == expected[fit]["fitted"]
            if mine[fit]["fitted"]:
                for key in ("median", "beta", "beta_total"):
                    assert mine[fit][key] == pytest.approx(expected[fit][key], rel=1e-12)
                # The same bootstrap (1000 resamples, the same seed): the same intervals.
                assert mine[fit]["bootstrap"] == expected[fit]["bootstrap"]
                for key in ("median_interval", "beta_interval"):
                    assert (key in mine[fit]) == (key in expected[fit])
                    if key in mine[fit]:
                        assert mine[fit][key] == pytest.approx(expected[fit][key], rel=1e-12)
    with pytest.raises(ValueError, match="limit 'sideways'"):
        study.fragility("sideways")
    # A limit is found as it was given to ida too.
    assert study.fragility("theta_over_alpha=0.01", "damper") == study.fragility("theta_over_alpha>=0.01", "damper")
    with pytest.raises(ValueError, match="--beta-modelling"):
        study.fragility("overturning", beta_modelling=-0.1)
    wider = study.fragility("overturning", "damper", beta_modelling=0.4)["capacity_fit"]
    if wider["fitted"]:
        assert wider["beta_total"] == pytest.approx((wider["beta"] ** 2 + 0.4 ** 2) ** 0.5)


def test_resurrections_count_as_the_program_counts_them(cli, records, tmp_path):
    """The first-collapse convention and 'keep' give the program's stripes and fractiles."""
    files = [records / "elcentro_1940_ns.at2", records / "christchurch2011_rehs_n02e.at2"]
    levels = [2, 4, 6, 8, 10, 12, 14]
    for convention in ("first", "keep"):
        out = tmp_path / convention
        r = cli.run("ida", "--record", *files, "--scales", ",".join(map(str, levels)), "--variants", "no-damper",
                    "--resurrection", convention, "--bootstrap", "0", "--out", out, "--no-plot")
        assert r.returncode == 0, r.stderr
        theirs = json.loads((out / "summary.json").read_text())
        assert theirs["resurrection"] == convention
        study = rocking.ida(None, [str(f) for f in files], levels=levels, variants=["no-damper"],
                            resurrection=convention)
        mine = study.fragility("overturning", bootstrap=0)
        assert mine["stripes"] == theirs["variants"][0]["fragility"][0]["stripes"]
        collapsed = [f["collapsed"] for f in study.fractiles("theta_over_alpha")]
        assert collapsed == theirs["variants"][0]["fractiles"]["theta_over_alpha"]["collapsed"]
        if convention == "first":
            assert collapsed == sorted(collapsed)  # once overturned, overturned
        else:
            assert collapsed != sorted(collapsed)  # Christchurch REHS stands again at 10 after overturning at 8
    with pytest.raises(ValueError, match="--resurrection 'sometimes'"):
        rocking.ida(None, [str(files[0])], levels=[1], variants=["no-damper"], resurrection="sometimes")


def test_a_thread_count_beyond_the_machine_is_capped_with_a_warning(elcentro):
    with pytest.warns(RuntimeWarning, match=r"threads 100000: this machine has \d+ cores; running \d+ threads"):
        study = rocking.ida(None, [str(elcentro)], levels=[1], variants=["no-damper"], threads=100000)
    assert len(study.rows) == 1 and study.rows[0]["outcome"] == "completed"
    with pytest.raises(ValueError, match=r"threads -1: must be at least 1"):
        rocking.ida(None, [str(elcentro)], levels=[1], threads=-1)


def test_an_ida_of_records_from_numpy_arrays_equals_the_ida_of_their_files_row_for_row(records):
    files = [records / "elcentro_1940_ns.at2", records / "kobe1995_kjma_000.at2"]
    arrays = []
    for f in files:
        loaded = rocking.Record.load(f)
        arrays.append(rocking.Record(np.array(loaded.acceleration), loaded.dt, units="m/s2", name=f.stem))
    from_files = rocking.ida(None, [str(f) for f in files], im="pga", levels=[0.5, 1.5], variants=["damper", "no-damper"])
    from_arrays = rocking.ida(None, arrays, im="pga", levels=[0.5, 1.5], variants=["damper", "no-damper"])
    assert from_arrays.records == [f.stem for f in files]
    assert len(from_files.rows) == len(from_arrays.rows) == 2 * 2 * 2
    for a, b in zip(from_files.rows, from_arrays.rows):
        assert {k: v for k, v in a.items() if k != "record"} == {k: v for k, v in b.items() if k != "record"}
    # Record objects read from files keep their paths as names.
    loaded = rocking.ida(None, [rocking.Record.load(f) for f in files], im="pga", levels=[0.5], variants=["damper"])
    assert loaded.records == [str(f) for f in files]
    with pytest.raises(TypeError, match="records: expected rocking.Record objects or paths"):
        rocking.ida(None, [3.5], levels=[1])


def test_a_hunt_through_python_equals_the_programs_hunt_csv(cli, records, tmp_path):
    files = [records / "elcentro_1940_ns.at2", records / "christchurch2011_rehs_n02e.at2"]
    out = tmp_path / "hunt"
    r = cli.run("ida", "--record", *files, "--im", "pga", "--levels", "0.5", "--hunt", "--hunt-max", "6",
                "--variants", "damper,no-damper", "--bootstrap", "200", "--out", out, "--no-plot")
    assert r.returncode == 0, r.stderr
    with open(out / "hunt.csv") as f:
        theirs = list(csv.DictReader(f))
    with open(out / "hunt_points.csv") as f:
        their_points = list(csv.DictReader(f))
    study = rocking.ida(None, [str(f) for f in files], im="pga", levels=[0.5], variants=["damper", "no-damper"],
                        hunt=True, hunt_max=6)
    assert study.rows == []
    assert len(study.hunts) == len(theirs) == 4
    for mine, row in zip(study.hunts, theirs):
        assert pathlib.Path(mine["record"]).name == row["record"]
        assert mine["variant"] == row["variant"]
        assert mine["runs"] == int(row["runs"])
        for key in ("collapse_level", "survived_level", "traced_level", "collapse_scale"):
            assert (mine[key] is None) == (row[key] == ""), key
            if mine[key] is not None:
                assert mine[key] == float(row[key]), key
        points = [p for p in their_points if p["record"] == row["record"] and p["variant"] == row["variant"]]
        # hunt_points.csv has 9 significant digits.
        assert [(p["why"], p["overturned"]) for p in mine["points"]] == \
            [(p["why"], bool(int(p["overturned"]))) for p in points]
        assert [p["level"] for p in mine["points"]] == pytest.approx([float(p["level"]) for p in points], rel=1e-8)
    summary = json.loads((out / "summary.json").read_text())
    for v, variant in enumerate(["damper", "no-damper"]):
        fit = study.fragility("overturning", variant, bootstrap=200)["capacity_fit"]
        expected = summary["variants"][v]["fragility"][0]["capacity_fit"]
        assert fit["fitted"] == expected["fitted"]
        if fit["fitted"]:
            assert fit["median"] == pytest.approx(expected["median"], rel=1e-12)
    with pytest.raises(ValueError, match="a hunt has none"):
        study.fractiles("theta_over_alpha")


def test_the_files_ida_write_makes_are_the_programs_byte_for_byte(cli, records, tmp_path):
    """rocking.study_files writes the rows and the report for both: Ida.write makes the
    files of `rocking ida --no-plot` (its inputs.txt, timing.csv and lock aside), and
    Ida.summary() is summary.json's dict."""
    files = [records / "elcentro_1940_ns.at2", records / "chichi1999_chy028_n.at2"]
    paths = [str(f) for f in files]
    cases = {
        "ladder": (["--scales", "0.5,1,2", "--variants", "damper,no-damper", "--limit", "theta_over_alpha=0.01"],
                   lambda: rocking.ida(None, paths, levels=[0.5, 1, 2], variants=["damper", "no-damper"],
                                       limits=["theta_over_alpha=0.01"])),
        "hunt": (["--im", "pga", "--levels", "0.5", "--hunt", "--hunt-max", "6", "--variants", "damper,fixed-base"],
                 lambda: rocking.ida(None, paths, im="pga", levels=[0.5], variants=["damper", "fixed-base"], hunt=True,
                                     hunt_max=6)),
    }
    for name, (args, run) in cases.items():
        theirs = tmp_path / name / "program"
        r = cli.run("ida", "--record", *files, *args, "--bootstrap", "200", "--out", theirs, "--no-plot")
        assert r.returncode == 0, r.stderr
        study = run()
        mine = study.write(tmp_path / name / "python", bootstrap=200)
        expected = sorted(p.name for p in theirs.iterdir() if p.name not in ("inputs.txt", "timing.csv", ".lock"))
        assert sorted(p.name for p in mine) == expected, name
        assert ("ida.csv" in expected) == (name == "ladder")
        for p in mine:
            assert p.read_bytes() == (theirs / p.name).read_bytes(), f"{name}: {p.name}"
        assert study.summary(bootstrap=200) == json.loads((theirs / "summary.json").read_text()), name
    with pytest.raises(ValueError, match="bootstrap -1"):
        study.write(tmp_path / "bad", bootstrap=-1)


def test_the_scene_names_its_devices_and_ida_runs_its_own_variants(elcentro):
    """The [damper] is the device "damper" as in the program's lists; with no
    variants given, ida runs the scene's own: as built, without each
    energy-dissipating device, and on a fixed base (as `rocking ida`)."""
    chimney = rocking.Scene.default()
    groups = chimney.device_groups
    assert [g["name"] for g in groups] == ["damper"]
    assert groups[0]["dissipates"] and groups[0]["prestress"] is None
    assert groups[0]["devices"] == ["damper_left", "damper_right"]
    assert groups[0]["removal"] == "device-=damper"
    wall = rocking.Scene.load(str(pathlib.Path(__file__).parents[2] / "data" / "scenes" / "controlled_rocking_wall.toml"))
    assert [(g["name"], g["dissipates"], g["prestress"]) for g in wall.device_groups] == \
        [("tendon", False, 2.6e6), ("dampers", True, None)]
    study = rocking.ida(wall, [str(elcentro)], levels=[1])
    assert study.variants == ["scene", "without:dampers", "fixed-base"]
    assert all(row["outcome"] != "failed" for row in study.rows)
