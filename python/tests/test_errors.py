"""Every error path: bad input raises tswm.InputError (a ValueError) whose
message is the command line's one line, and nothing is written; other
failures raise tswm.Error."""

import pytest

import tswm


def cli_error(cli, *args):
    """The one line `tswm ARGS` prints for bad input (exit code 2), without
    its `tswm: error: `."""
    p = cli(*args, check=False)
    assert p.returncode == 2, p.stderr
    (line,) = p.stderr.strip().splitlines()
    return line.removeprefix("tswm: error: ")


def input_error(call):
    with pytest.raises(tswm.InputError) as e:
        call()
    assert isinstance(e.value, ValueError) and isinstance(e.value, tswm.Error)
    return str(e.value)


BAD_SWEEPS = [
    '[base]\ngamma_deg = 100.0\n',
    '[base]\nmu = 0.05\n',
    '[base]\nm1 = "heavy"\n',
    '[[grid]]\nparam = "gama_deg"\nvalues = [1, 2]\n',
    '[[grid]]\nparam = "f2"\nfrom = 1\nto = 2\nn = 0\n',
    '[base\n',
    '[base]\nfriction = "teflon"\n',
    '[sampling]\nn = 10\n',
]


@pytest.mark.parametrize("text", BAD_SWEEPS)
def test_a_bad_sweep_file_is_the_command_lines_line(cli, tmp_path, text):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    want = cli_error(cli, "run", f, "--out", tmp_path / "cli")
    out = tmp_path / "py"
    assert input_error(lambda: tswm.run(f, out=out, progress=False)) == want
    assert not out.exists()
    assert not (tmp_path / "cli").exists()


def test_a_bad_dict_names_the_key_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    msg = input_error(lambda: tswm.run({"base": {"gamma_deg": 100.0}}, out=out, progress=False))
    assert "sweep['base']['gamma_deg']" in msg and "must be in [0.5, 85] deg" in msg
    msg = input_error(
        lambda: tswm.run({"grid": [{"param": "f2", "values": [1.0]}, {"param": "gama_deg", "values": [5.0]}]})
    )
    assert "sweep['grid'][1]" in msg and "gamma_deg" in msg
    assert not out.exists()


def test_toml_text_names_its_line():
    msg = input_error(lambda: tswm.run("[base]\nf2 = 1.0\ngamma_deg = 0.1\n", progress=False))
    assert msg.startswith("sweep: lane 0 (line 3): gamma_deg: must be in [0.5, 85] deg"), msg


def test_a_bad_lane_table_file_is_the_command_lines_line(cli, tmp_path):
    f = tmp_path / "lanes.csv"
    for text in ["gamma_deg,f2\n5,1\n100,2\n", "gamma,f2\n5,1\n", "f2\nheavy\n", "f2\n"]:
        f.write_text(text)
        want = cli_error(cli, "run", "--lanes", f, "--out", tmp_path / "cli")
        assert input_error(lambda: tswm.run(lanes=f, out=tmp_path / "py", progress=False)) == want
        assert not (tmp_path / "py").exists()


def test_a_bad_data_frame_names_the_lane_and_column(tmp_path):
    import pandas as pd

    out = tmp_path / "out"
    df = pd.DataFrame({"gamma_deg": [5.0, 8.0, 100.0], "f2": [1.0, 2.0, 3.0]})
    msg = input_error(lambda: tswm.run(lanes=df, out=out, progress=False))
    assert msg.startswith("lanes: lane 2: gamma_deg: must be in [0.5, 85] deg"), msg
    msg = input_error(lambda: tswm.run(lanes=pd.DataFrame({"gama_deg": [5.0]}), progress=False))
    assert msg.startswith("lanes: gama_deg: unknown column (did you mean `gamma_deg`?)"), msg
    msg = input_error(lambda: tswm.run(lanes=pd.DataFrame({"motor": [1.0]}), progress=False))
    assert "motor: `1` is not a motor law; allowed: kloss, constant" in msg, msg
    msg = input_error(lambda: tswm.run(lanes=pd.DataFrame({"f2": [True]}), progress=False))
    assert msg.startswith("lanes: f2: holds Boolean; allowed: numbers"), msg
    msg = input_error(lambda: tswm.run(lanes=pd.DataFrame({"f2": [float("inf")]}), progress=False))
    assert "lane 0: f2" in msg and "not finite" in msg, msg
    assert not out.exists()


def test_bad_arguments_are_input_errors(root, tmp_path):
    paper = root / "sweeps/paper.toml"
    for kw, want in [
        ({"backend": "tpu"}, "backend: `tpu` is not a backend; allowed: auto, cpu, gpu"),
        ({"format": "xlsx"}, "format: `xlsx` is not a format; allowed: csv, parquet"),
        ({"threads": 0}, "threads: 0 is not allowed; allowed: 1 to 1024 (this machine runs"),
        ({"tol": 1.0}, "--tol: 1e0 is not allowed"),
        ({"precision": "f16"}, "precision: `f16` is not a precision; allowed: auto, f32, f64"),
    ]:
        msg = input_error(lambda: tswm.run(paper, out=tmp_path / "o", progress=False, **kw))
        assert msg.startswith(want), msg
    assert input_error(lambda: tswm.run(progress=False)).startswith("name a sweep file")
    assert "does-not-exist.toml" in input_error(lambda: tswm.run(tmp_path / "does-not-exist.toml"))
    assert not (tmp_path / "o").exists()
    with pytest.raises(TypeError):
        tswm.run(3.5)
    with pytest.raises(TypeError):
        tswm.run(paper, lanes=object())


def test_reading_a_folder_that_is_none(tmp_path):
    assert "holds no lanes.csv or lanes.parquet" in input_error(lambda: tswm.read(tmp_path))
    assert "holds no summary.csv" in input_error(lambda: tswm.summary(tmp_path))
    assert "holds no sensitivity.csv" in input_error(lambda: tswm.sensitivity(tmp_path))
    assert "is not a folder" in input_error(lambda: tswm.report(tmp_path / "nowhere"))


def test_a_folder_that_cannot_be_written_is_an_error_not_bad_input(root):
    with pytest.raises(tswm.Error) as e:
        tswm.run(root / "sweeps/paper.toml", out="/proc/tswm-cannot-write-here", progress=False)
    assert not isinstance(e.value, tswm.InputError)
