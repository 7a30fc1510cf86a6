"""The example runs as written and its answer agrees with the closed form."""

import importlib.util
import math

import pytest


def test_the_design_example(root, tmp_path):
    pytest.importorskip("matplotlib", reason="the example draws with matplotlib (pip install matplotlib)")
    pytest.importorskip("scipy", reason="the example searches with scipy (pip install scipy)")
    spec = importlib.util.spec_from_file_location("design", root / "python/examples/design.py")
    design = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(design)
    gamma, closed_form, lanes = design.main(str(tmp_path), drives=1000)
    assert (tmp_path / "efficiency_map.png").stat().st_size > 10_000
    # 1000 drives resolve the 1 % quantile of mu_static to 1/1000 of its
    # +-25 % range: tan(gamma) within 0.045 / 1000 of the closed form's.
    assert abs(math.tan(math.radians(gamma)) - math.tan(math.radians(closed_form))) < 2 * 0.045 / 1000
    assert lanes % 1000 == 0 and lanes >= 3000
