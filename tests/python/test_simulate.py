"""rocking.simulate, rocking.modal and rocking.Record against the program:
the same library, the same defaults, the same numbers."""
import json

import numpy as np
import pytest

import rocking


def without_wall_time(summary):
    summary = dict(summary)
    del summary["wall_s"]  # the one entry that depends on the machine's load
    return summary


def test_chimney_under_el_centro_equals_the_programs_summary_number_for_number(cli, elcentro, tmp_path):
    out = tmp_path / "cli"
    r = cli.run("simulate", "--record", elcentro, "--out", out)
    assert r.returncode == 0, r.stderr
    expected = json.loads((out / "summary.json").read_text())
    result = rocking.simulate(rocking.Scene.default(), str(elcentro))
    assert without_wall_time(result.summary) == without_wall_time(expected)
    assert result.peaks == expected["peaks"]
    assert result.outcome == "completed"
    # The history: history.csv's columns, printed there to 9 significant digits.
    csv = np.genfromtxt(out / "history.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    header = (out / "history.csv").read_text().splitlines()[0].split(",")
    names = [h.split(" [")[0] for h in header]
    assert list(result.history) == names
    n = len(csv)
    assert len(result.history["t"]) == n
    for i, name in enumerate(names):
        column = csv[csv.dtype.names[i]]
        if name == "phase":
            phase = np.select([column == "contact", column == "rock+"], [0.0, 1.0], -1.0)
            np.testing.assert_array_equal(result.history["phase"], phase)
        else:
            np.testing.assert_allclose(result.history[name], column, rtol=1e-8, atol=0, err_msg=name)


def test_a_record_from_a_numpy_array_runs_as_the_same_record_read_from_its_file(elcentro):
    from_file = rocking.Record.load(elcentro)
    acc = from_file.acceleration
    from_array = rocking.Record(acc, from_file.dt, units="m/s2")
    a = rocking.simulate(record=from_file)
    b = rocking.simulate(record=from_array)
    assert a.peaks == b.peaks
    assert a.events == b.events
    np.testing.assert_array_equal(a.history["theta"], b.history["theta"])
    # The same in g: one rounding per sample (x / 9.81 x 9.81), nothing more.
    in_g = rocking.simulate(record=rocking.Record(acc / 9.81, from_file.dt, units="g"))
    for key, value in a.peaks.items():
        if value is not None:
            assert in_g.peaks[key] == pytest.approx(value, rel=1e-6), key


def test_history_arrays_are_handed_over_without_a_copy_per_element(elcentro):
    result = rocking.simulate(record=str(elcentro))
    t = result.history["t"]
    assert isinstance(t, np.ndarray) and t.dtype == np.float64 and t.ndim == 1
    assert t.base is not None and type(t.base).__name__ == "PyCapsule"  # owns the C++ vector, no copy
    assert np.all(np.diff(t) >= 0)
    assert all(len(v) == len(t) for v in result.history.values())


def test_events_are_the_runs_phase_changes(elcentro):
    result = rocking.simulate(record=str(elcentro))
    kinds = [e["kind"] for e in result.events]
    counts = result.summary["counts"]
    assert kinds.count("uplift") == counts["uplifts"] > 0
    assert kinds.count("impact") == counts["impacts"] > 0
    uplifts = [e for e in result.events if e["kind"] == "uplift"]
    assert uplifts[0]["t"] == result.summary["first_uplift_s"]
    times = [e["t"] for e in result.events]
    assert times == sorted(times)
    assert all(e["pivot"] in (-1, 1) for e in result.events)


def test_a_run_that_cannot_finish_raises_run_error_with_what_it_reached(elcentro):
    with pytest.raises(rocking.RunError) as caught:
        rocking.simulate(record=str(elcentro), max_steps=200)
    assert "200" in str(caught.value)
    partial = caught.value.result
    assert partial.outcome == "failed"
    assert partial.summary["failure"] == str(caught.value)
    assert 0 < partial.history["t"][-1] < 10


def test_modal_equals_the_programs_modal_json(cli):
    assert rocking.modal() == cli.json("modal", "--json")
    soft = rocking.Scene.default().set("structure.EI_scale", 0.25)
    assert rocking.modal(soft) == cli.json("modal", "--json", "--set", "structure.EI_scale=0.25")
    block = rocking.Scene.load(cli_scene("rigid_block.toml"))
    assert rocking.modal(block) == cli.json("modal", cli_scene("rigid_block.toml"), "--json")


def cli_scene(name):
    from conftest import SCENES
    return str(SCENES / name)


def test_scene_set_replaces_a_key_copies_are_independent_and_to_toml_reads_back(tmp_path):
    scene = rocking.Scene.default()
    assert scene.devices == ["damper_left", "damper_right"]
    other = scene.copy().set("damper.enabled", False)
    assert other.devices == [] and scene.devices == ["damper_left", "damper_right"]
    other.set("damper.enabled", True).set("damper.thickness", 1.5)
    assert other.overrides == ["damper.enabled=true", "damper.thickness=1.5"]
    text = other.to_toml()
    path = tmp_path / "scene.toml"
    path.write_text(text)
    assert rocking.modal(rocking.Scene.load(path)) == rocking.modal(other)
    assert rocking.modal(other) != rocking.modal(scene)
    tendon = scene.copy().set("device+", {"kind": "elastic", "at": 0, "kinematics": "vertical",
                                          "free_length": 33, "P0": 2e6, "k": 5e7, "name": "tendon"})
    assert tendon.devices[-1] == "tendon"


def test_record_measures_are_the_programs_json_key_for_key(cli, elcentro):
    record = rocking.Record.load(elcentro)
    mine = record.measures([0.5, 1.0])
    theirs = cli.json("record", elcentro, "--periods", "0.5,1", "--json")
    theirs = theirs[0] if isinstance(theirs, list) else theirs
    assert sorted(mine) == sorted(theirs)
    for key, value in theirs.items():
        if key in ("id", "file"):
            continue  # the program names the file as given on its command line
        assert mine[key] == value, key
    assert record.pga_g == theirs["pga_g"]


def test_a_records_arrays_are_read_only_copies(elcentro):
    record = rocking.Record.load(elcentro)
    for name in ("acceleration", "times"):
        array = getattr(record, name)
        assert not array.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0
    changed = record.acceleration.copy()
    changed[0] += 1.0  # a copy is the user's to change, and makes a new record
    assert rocking.Record(changed, record.dt, units="m/s2").acceleration[0] == changed[0]


def test_to_pandas_gives_the_history_or_says_what_it_needs():
    result = rocking.simulate(duration=0.5)
    try:
        import pandas  # noqa: F401  (not a dependency of the project)
    except ImportError:
        with pytest.raises(ImportError, match="python3-pandas"):
            result.to_pandas()
    else:
        frame = result.to_pandas()
        assert list(frame.columns) == list(result.history)
        assert len(frame) == len(result.history["t"])


def test_the_walls_devices_are_reported_under_their_names():
    from conftest import SCENES
    wall = rocking.Scene.load(str(SCENES / "controlled_rocking_wall.toml"))
    result = rocking.simulate(wall, every=0.0005)
    assert "damper_d" not in result.peaks and "damper_d" not in result.history
    for name in ("tendon", "dampers_left", "dampers_right"):
        peak = result.peaks[name + ".elongation"]
        assert np.nanmax(np.abs(result.history[name + ".elongation"])) == pytest.approx(peak, rel=2e-3)
    assert result.peaks["tendon.force"] > result.peaks["dampers_left.force"]


def test_columns_choose_the_history_as_history_does_on_the_command_line():
    full = rocking.simulate()
    chosen = rocking.simulate(columns=["theta", "a_N", "damper_left.force"])
    assert list(chosen.history) == ["t", "theta", "a_N", "damper_left.force"]
    for name in chosen.history:
        np.testing.assert_array_equal(chosen.history[name], full.history[name])
    with pytest.raises(ValueError, match="columns nope: unknown quantity"):
        rocking.simulate(columns=["nope"])


def test_quantities_name_what_a_run_reports():
    from conftest import SCENES
    wall = rocking.Scene.load(str(SCENES / "controlled_rocking_wall.toml"))
    listed = {q["name"]: q for q in rocking.quantities(wall)}
    assert listed["tendon.force"]["unit"] == "N" and listed["tendon.force"]["study"]
    assert not listed["damper_d"]["reported"]
    result = rocking.simulate(wall, history=True)
    assert list(result.history) == [n for n, q in listed.items() if q["history"] and q["reported"]]
    assert set(result.peaks) == {n for n, q in listed.items() if q["peak"] and q["reported"]}


def test_nodes_elements_and_the_scenes_output_table_as_on_the_command_line(cli, tmp_path):
    chosen = ["node4.x_abs", "element1.V", "x_g", "node4.x"]
    result = rocking.simulate(columns=chosen, every=0.02)
    assert list(result.history) == ["t"] + chosen
    h = result.history
    np.testing.assert_allclose(h["node4.x_abs"], h["node4.x"] + h["x_g"], rtol=0, atol=1e-12)
    out = tmp_path / "run"
    assert cli.run("simulate", "--history", ",".join(chosen), "--every", "0.02", "--out", out).returncode == 0
    header = (out / "history.csv").read_text().splitlines()[0]
    assert header == "t [s],node4.x_abs [m],element1.V [N],x_g [m],node4.x [m]"
    # The scene's [output] table: its columns and interval unless columns= and every= are given.
    scene = rocking.Scene.default().set("output.history", ["theta", "node2.u"]).set("output.interval", 0.05)
    own = rocking.simulate(scene)
    assert list(own.history) == ["t", "theta", "node2.u"]
    assert own.history["t"][1] == pytest.approx(0.05)
    assert list(rocking.simulate(scene, columns=["delta_t"]).history) == ["t", "delta_t"]
    with pytest.raises(ValueError, match="columns node9.u: no node 9"):
        rocking.simulate(columns=["node9.u"])


def test_a_vertical_motion_runs_as_the_programs_and_a_record_in_the_wrong_direction_is_refused(cli, records, tmp_path):
    waiau = records / "formats" / "20161113_110259_WTMC_20.V2A"
    out = tmp_path / "cli"
    r = cli.run("simulate", "--record", waiau, "--component", "N28W", "--vertical", "Up", "--duration", "60",
                "--out", out)
    assert r.returncode == 0, r.stderr
    expected = json.loads((out / "summary.json").read_text())
    horizontal = rocking.Record.load(waiau, component="N28W")
    up = rocking.Record.load(waiau, component="Up")
    by_name = rocking.simulate(rocking.Scene.default(), horizontal, vertical="Up", duration=60)
    by_record = rocking.simulate(rocking.Scene.default(), horizontal, vertical=up, duration=60)
    for result in (by_name, by_record):
        assert result.peaks == expected["peaks"]
        assert result.summary["vertical_motion"] == expected["vertical_motion"]
        np.testing.assert_array_equal(result.history["a_v"], by_name.history["a_v"])
    assert np.abs(by_name.history["a_v"]).max() > 1.0
    assert "a_v" not in rocking.simulate(rocking.Scene.default(), horizontal, duration=5).history
    with pytest.raises(ValueError, match="component Up, a vertical one"):
        rocking.simulate(rocking.Scene.default(), up)
    with pytest.raises(ValueError, match="component N28W, a horizontal one"):
        rocking.simulate(rocking.Scene.default(), horizontal, vertical=horizontal)


def test_rotd_and_an_azimuth_as_the_program_computes_them(cli, records, tmp_path):
    waiau = records / "formats" / "20161113_110259_WTMC_20.V2A"
    r = cli.run("record", waiau, "--component", "N28W", "--rotd", "--periods", "0.2,1,3", "--json")
    assert r.returncode == 0, r.stderr
    expected = json.loads(r.stdout)[0]
    n28w = rocking.Record.load(waiau, component="N28W")
    s62w = rocking.Record.load(waiau, component="S62W")
    got = rocking.rotd(n28w, s62w, periods=[0.2, 1, 3])
    assert got["rotd50_g"] == expected["rotd50_g"]
    assert got["rotd100_g"] == expected["rotd100_g"]
    out = tmp_path / "cli"
    r = cli.run("simulate", "--record", waiau, "--component", "N28W", "--azimuth", "30", "--duration", "60",
                "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    turned = rocking.simulate(rocking.Scene.default(), n28w, azimuth=30, second=s62w, duration=60)
    assert turned.peaks == summary["peaks"]
    assert "30 deg from N28W toward S62W" in summary["motion"]


def test_a_processed_record_measures_as_the_program_measures_it(cli, records):
    knet = records / "formats" / "AOM0011801241951.EW"
    spec = "detrend=1,taper=0.05,highpass=0.1,lowpass=20"
    r = cli.run("record", knet, "--process", spec, "--json")
    assert r.returncode == 0, r.stderr
    raw, processed = json.loads(r.stdout)
    rec = rocking.Record.load(knet, process=spec)
    got = rec.measures()
    for key in ("pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "psa_g", "processing"):
        assert got[key] == processed[key], key
    assert got["pgd_m"] < 0.2 * raw["pgd_m"]
    assert "processed: detrend 1" in rec.description
    with pytest.raises(ValueError, match="process hp=1: hp=1: unknown key"):
        rocking.Record.load(knet, process="hp=1")
