"""The example runs as written and its answer agrees with the closed form."""

import importlib.util
import math

import pytest


def test_the_design_example(root, tmp_path):
    pytest.importorskip("matplotlib", reason="the example draws with matplotlib (pip install matplotlib)")
    spec = importlib.util.spec_from_file_location("design", root / "python/examples/design.py")
    design = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(design)
    gamma, (lo95, hi95), bound, closed_form, lanes = design.main(str(tmp_path), drives=1000)
    assert (tmp_path / "efficiency_map.png").stat().st_size > 10_000
    # The sample 1 % quantile of 1000 independent draws of mu_static
    # (uniform over a range of 0.045) has a standard error of about
    # 0.045 * sqrt(0.01 * 0.99 / 1000): tan(gamma) within three of them of
    # the closed form's; the 95 % interval holds it, the one-sided bound
    # lies below the estimate.
    se = 0.045 * math.sqrt(0.01 * 0.99 / 1000)
    assert abs(math.tan(math.radians(gamma)) - math.tan(math.radians(closed_form))) < 3 * se
    assert lo95 <= closed_form <= hi95
    assert bound <= gamma
    # The search integrates far fewer lanes than a tolerance study a step
    # (brentq took 18 steps of 1000 drives).
    assert 1000 < lanes <= 6000
