"""Every ```python block of README.md and docs/python.md runs as written, and its answer is checked.

The blocks build a linear inverted pendulum and log its COM; the expected values are the LIP's closed form
x(t) = x0 cosh(lt) + L0/(z0 l) sinh(lt) with l = sqrt(g / z0), never the code under test.
"""
import math
import os
import pathlib
import re

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", ROOT / "docs" / "python.md"]


def python_blocks(page):
    return re.findall(r"^```python\n(.*?)^```", page.read_text(encoding="utf-8"), flags=re.S | re.M)


def test_the_pages_have_python_blocks():
    assert python_blocks(ROOT / "README.md"), "README.md shows no Python example"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_each_block_runs_and_follows_the_closed_form(page, tmp_path, monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    for k, code in enumerate(python_blocks(page), start=1):
        scope = {"__name__": f"{page.name}_block_{k}"}
        exec(compile(code, f"{page}:block {k}", "exec"), scope)
        if "log" not in scope:
            continue
        x0, L0 = -0.15, 0.5  # the blocks' initial state, as written in them
        match = re.search(r"z0=([0-9.]+)", code)
        z0 = float(match.group(1)) if match else 0.8
        lam = math.sqrt(9.81 / z0)
        t = np.asarray(scope["log"]["time"])
        x = x0 * np.cosh(lam * t) + L0 / (z0 * lam) * np.sinh(lam * t)
        assert t[-1] == pytest.approx(0.6, abs=0.011)
        assert np.max(np.abs(np.asarray(scope["log"]["lip.state[0]"]) - x)) < 1e-5
        for png in re.findall(r'savefig\("([^"]+)"\)', code):
            assert os.path.getsize(png) > 1000, f"{page.name} block {k}: {png} is empty"
