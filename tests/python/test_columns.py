"""rocking.simulate on a structure on rocking columns (MODEL.md 16): the
columns' histories under the names history.csv gives them (columns.theta,
beam.x, ...) and summary.json's columns object, as `rocking simulate` writes
them for the same scene."""
import numpy as np

from conftest import SCENES, program_and_module


def test_a_frame_hands_over_its_columns_histories_and_summary_as_the_program_writes_them(cli, tmp_path):
    expected, names, rows, result = program_and_module(cli, tmp_path, SCENES / "rocking_frame.toml")
    assert list(result.history) == names
    for name in ("columns.theta", "columns.theta_over_alpha", "columns.theta_dot", "beam.x", "columns.top_force_min"):
        assert name in result.history, name
    assert len(result.history["t"]) == len(rows)
    for i, name in enumerate(names):
        if name == "phase":
            continue  # written as words
        column = np.array([float(row[i]) for row in rows])
        np.testing.assert_allclose(result.history[name], column, rtol=1e-8, atol=1e-300, err_msg=name)
    columns = result.summary["columns"]
    assert columns == expected["columns"]
    assert columns["uplifts"] > 0 and columns["impacts"] > 0
    # The piers (1.6 m wide, 9.6 m tall): theta over alpha is theta over atan(0.8 / 4.8), row by row.
    np.testing.assert_allclose(result.history["columns.theta_over_alpha"],
                               result.history["columns.theta"] / np.arctan(0.8 / 4.8), rtol=1e-12, atol=1e-300)
    # The beam stays on the piers: every top contact force is compressive.
    assert np.min(result.history["columns.top_force_min"]) > 0
    assert columns["smallest_top_force_N"] > 0
