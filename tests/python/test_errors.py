"""Every scene error the program's tests exercise raises ValueError in Python
with the program's own one-line message (tests/cli_test.cpp,
hostile_input_test.cpp, first_use_test.cpp), whether the overrides come with
the scene or one by one through Scene.set."""
import pytest

import rocking
from conftest import SCENES

BAD_OVERRIDES = [
    ["structure.masses=[1,-2,3,4]"],
    ["structure"],
    ["structure.EI_scale=1e300"],
    ["structure.youngs_modulus=1e308"],
    ["structure.masses=[1e15,1,1,1]"],
    ["excitation.duration=1e9"],
    ["initial.u=[1,2]"],
    ["contact.rocking=false", "initial.theta=0.1"],
    ["structure.no_such_key=1"],
    ["damper.enabled=maybe"],
    ['device+={kind="no-such-law"}'],
    ["structure.masses=[1e-300,1,1,1]"],
    ["damper.theta_y=7"],
    ["damper.thickness=1e300"],
    ['device+={name="t", kind="elastic", at=0, kinematics="vertical", free_length=33, P0=1e300, k=5e7}'],
    ['device+={name="p", kind="bouc-wen", at="edges", k=1e7, eps=0.05, d_y=0.02, alpha=0, beta=0}'],
    ["excitation.scale=0"],
]


@pytest.mark.parametrize("overrides", BAD_OVERRIDES, ids=lambda o: " ".join(o))
def test_a_bad_override_raises_value_error_with_the_programs_message(cli, overrides):
    expected = cli.error("modal", *[a for o in overrides for a in ("--set", o)])
    with pytest.raises(ValueError) as caught:
        rocking.Scene.default(overrides)
    assert str(caught.value) == expected
    scene = rocking.Scene.default()
    with pytest.raises(ValueError) as caught:
        for o in overrides:
            scene.set(o)
    assert str(caught.value) == expected
    assert scene.overrides == overrides[:-1]  # the bad one is not kept


@pytest.mark.parametrize("path", ["/no/such/scene.toml", str(SCENES)], ids=["missing", "a folder"])
def test_a_bad_scene_file_raises_value_error_with_the_programs_message(cli, path):
    expected = cli.error("modal", path)
    with pytest.raises(ValueError) as caught:
        rocking.Scene.load(path)
    assert str(caught.value) == expected


def test_a_rigid_block_on_a_fixed_base_is_refused_as_by_the_program(cli):
    block = str(SCENES / "rigid_block.toml")
    expected = cli.error("modal", block, "--set", "contact.rocking=false")
    with pytest.raises(ValueError) as caught:
        rocking.Scene.load(block).set("contact.rocking", False)
    assert str(caught.value) == expected


def test_bad_run_options_and_records_raise_value_error_naming_them(tmp_path):
    with pytest.raises(ValueError, match=r"^rtol 2: must be in \[1e-13, 0.1\]$"):
        rocking.simulate(rtol=2)
    with pytest.raises(ValueError, match=r"^every 0: must be positive$"):
        rocking.simulate(every=0)
    with pytest.raises(ValueError, match="unknown"):
        rocking.simulate(integrator="euler")
    with pytest.raises(ValueError, match=r"^Record: dt -1: must be positive$"):
        rocking.Record([0.0, 0.1], dt=-1)
    with pytest.raises(ValueError, match=r"acc\[1\] is nan"):
        rocking.Record([0.0, float("nan")], dt=0.01)
    with pytest.raises(ValueError, match="unit"):
        rocking.Record([0.0, 0.1], dt=0.01, units="furlongs")
    with pytest.raises(ValueError, match="record file not found|not found"):
        rocking.Record.load(tmp_path / "none.at2")


def test_arguments_of_the_wrong_type_raise_type_error_naming_them(elcentro):
    with pytest.raises(TypeError, match=r"^scene: expected a rocking.Scene or None, got int$"):
        rocking.simulate(3)
    with pytest.raises(TypeError, match=r"^record: expected a rocking.Record, a path or None, got float$"):
        rocking.simulate(None, 2.5)
    with pytest.raises(TypeError, match=r"^records: expected rocking.Record objects or paths of records, folders or lists, got int$"):
        rocking.ida(None, [str(elcentro), 7], levels=[1])
    with pytest.raises(TypeError, match=r"^records: expected rocking.Record objects or paths of records, folders or lists, got float$"):
        rocking.ida(None, 1.5, levels=[1])


def test_every_public_function_class_and_property_says_what_it_does():
    """Read from the module itself: a new function or property without a docstring fails."""
    import inspect

    def described(obj):
        doc = inspect.getdoc(obj) or ""
        # pybind11 puts the signature on the first line of a function's docstring.
        lines = [line for line in doc.splitlines() if line.strip() and not line.startswith(getattr(obj, "__name__", "?") + "(")]
        return bool(lines)

    missing = []
    for name, obj in vars(rocking).items():
        if name.startswith("_") or inspect.ismodule(obj):
            continue
        if inspect.isclass(obj):
            if not described(obj):
                missing.append(name)
            for attr, member in vars(obj).items():
                if attr.startswith("_") or not (isinstance(member, property) or callable(member)):
                    continue
                if not described(member):
                    missing.append(f"{name}.{attr}")
        elif callable(obj) and not described(obj):
            missing.append(name)
    assert missing == []


def test_a_bad_limit_is_refused_before_the_records_as_by_the_program(cli, tmp_path):
    """--limit is parsed once, before any record is read: a study with a bad
    limit and a missing record names the limit, in Python as in the program."""
    missing = str(tmp_path / "none.at2")
    expected = cli.error("ida", "--record", missing, "--scales", "1", "--limit", "no_such_quantity=1")
    assert expected.startswith("--limit 'no_such_quantity=1': expected QUANTITY=VALUE")
    with pytest.raises(ValueError) as caught:
        rocking.ida(None, missing, levels=[1], limits=["no_such_quantity=1"])
    assert str(caught.value) == expected
