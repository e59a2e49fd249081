"""rocking.simulate on a structure that rocks at more than one level
(MODEL.md 15): the joints' histories under the names history.csv gives them
(joint1.theta, ...) and summary.json's joints list, as `rocking simulate`
writes them for the same scene."""
import json

import numpy as np

import rocking
from conftest import SCENES, program_and_module


def test_a_jointed_scene_hands_over_its_joints_histories_and_summary_as_the_program_writes_them(cli, tmp_path):
    expected, names, rows, result = program_and_module(cli, tmp_path, SCENES / "stacked_blocks.toml")
    # The same columns in the same order, the joint's among them.
    assert list(result.history) == names
    for name in ("joint1.theta", "joint1.theta_dot", "joint1.phase"):
        assert name in result.history, name
    assert len(result.history["t"]) == len(rows)
    for i, name in enumerate(names):
        if name == "phase":
            continue  # written as words; the joint's phase is a number
        column = np.array([float(row[i]) for row in rows])
        np.testing.assert_allclose(result.history[name], column, rtol=1e-8, atol=1e-300, err_msg=name)
    # The artefact rocks on the plinth: its joint's angle moves, and its peak is the summary's.
    theta = result.history["joint1.theta"]
    assert np.max(np.abs(theta)) > 1e-3
    joints = result.summary["joints"]
    assert joints == expected["joints"]
    assert [j["joint"] for j in joints] == [0, 1]
    assert joints[1]["uplifts"] > 0 and joints[1]["impacts"] > 0
    # Rows are kept every 0.01 s and at every event: the history's peak is the
    # summary's to within what the rows miss between two of them.
    assert np.max(np.abs(theta)) <= joints[1]["peak_theta"] * (1 + 1e-12)
    assert np.max(np.abs(theta)) >= 0.99 * joints[1]["peak_theta"]
    # Each event says where it happened; the artefact's uplifts are at joint 1.
    assert {e["joint"] for e in result.events} <= {0, 1}
    uplifts = [e for e in result.events if e["kind"] == "uplift" and e["joint"] == 1]
    assert len(uplifts) == joints[1]["uplifts"]
    assert uplifts[0]["t"] == joints[1]["first_uplift_s"]
    phase = result.history["joint1.phase"]
    assert set(np.unique(phase)) <= {-1.0, 0.0, 1.0}
    assert np.any(phase != 0)


def test_a_joints_quantities_are_listed_and_chosen_by_name():
    scene = rocking.Scene.load(str(SCENES / "stacked_blocks.toml"))
    listed = {q["name"]: q for q in rocking.quantities(scene)}
    assert listed["jointK.theta_over_alpha"]["study"] and not listed["jointK.theta_over_alpha"]["history"]
    chosen = rocking.simulate(scene, columns=["theta", "joint1.theta", "joint1.theta_over_alpha"])
    assert list(chosen.history) == ["t", "theta", "joint1.theta", "joint1.theta_over_alpha"]
    alpha_1 = np.arctan(0.15 / 0.45)  # the artefact: B_1 = 0.15 m, its centre of mass 0.45 m above its joint
    np.testing.assert_allclose(chosen.history["joint1.theta_over_alpha"], chosen.history["joint1.theta"] / alpha_1,
                               rtol=1e-12, atol=0)


def test_a_separated_run_names_its_joint_as_the_program_does(cli, tmp_path):
    """The cracked chimney under its pulse ends separated (a joint in tension,
    MODEL.md 15): Python's outcome and summary name the separating joint and
    the time as the program's summary.json does, on the rocking base (joint
    0, at the base's first impact) and on a fixed base (joint 1, the crack)."""
    scene_file = SCENES / "chimney_cracked.toml"
    expected, _, _, result = program_and_module(cli, tmp_path, scene_file)
    assert result.outcome == expected["outcome"] == "separated"
    assert result.summary["separated_joint"] == expected["separated_joint"] == 0
    assert result.summary["separation"] == expected["separation"]
    out = tmp_path / "fixed"
    r = cli.run("simulate", scene_file, "--set", "contact.rocking=false", "--out", out)
    assert r.returncode == 0, r.stderr
    fixed = rocking.simulate(rocking.Scene.load(str(scene_file), ["contact.rocking=false"]))
    assert fixed.outcome == "separated"
    assert fixed.summary["separated_joint"] == json.loads((out / "summary.json").read_text())["separated_joint"] == 1


def test_a_sliding_run_states_its_joint_as_the_program_does(cli, tmp_path):
    """A joint's friction demand reaching its stated limit ends the run as
    `sliding` (MODEL.md 15: sliding is not modelled): Python's outcome and
    statement are the program's summary.json's."""
    scene_file = SCENES / "stacked_blocks.toml"
    out = tmp_path / "sliding"
    r = cli.run("simulate", scene_file, "--set", "joint[0].friction=0.2", "--out", out)
    assert r.returncode == 0, r.stderr
    expected = json.loads((out / "summary.json").read_text())
    result = rocking.simulate(rocking.Scene.load(str(scene_file), ["joint[0].friction=0.2"]))
    assert result.outcome == expected["outcome"] == "sliding"
    assert result.summary["sliding"] == expected["sliding"]
    assert result.summary["sliding"].startswith("joint 1 at t = ")
