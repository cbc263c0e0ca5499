"""explain_plot.py: the numbers drawn add up (eq. 44) and the PNG is written."""

from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from urdfinertia.analysis.explain import explain_link
from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import load_spec
from urdfinertia.cli import main
from urdfinertia.descriptions.urdf.read import read_urdf
from urdfinertia.render.explain_plot import plot_breakdown

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


@pytest.fixture(scope="module")
def breakdown():
    robot, _ = read_urdf(ROBOTS / "nm7mar.urdf")
    spec = load_spec(ROBOTS / "nm7mar.inertia.toml")
    return explain_link(robot, "link1", FixOptions(spec=spec))


def test_shares_add_up_to_the_link_total(breakdown, tmp_path):
    drawn = plot_breakdown(breakdown, tmp_path / "b.png")
    percent = np.array(drawn["percent"])
    # sum_p I_p,s = I_s (eq. 44): every column of element shares adds up to 100 %
    np.testing.assert_allclose(percent.sum(axis=0), 100.0, rtol=1e-9)
    assert drawn["elements"] == [eb.element.name for eb in breakdown.elements]
    # an independent projection of each element's tensor on the link's principal axes
    axes, moments = breakdown.axes, breakdown.moments
    for row, eb in zip(percent, breakdown.elements, strict=True):
        expected = [axes[:, k] @ eb.element.inertia_link @ axes[:, k] / moments[k] * 100
                    for k in range(3)]
        np.testing.assert_allclose(row[1:], expected, rtol=1e-9)


def test_cli_writes_a_png(tmp_path):
    png = tmp_path / "explain.png"
    assert main(["explain", str(ROBOTS / "nm7mar.urdf"), "--link", "link2", "--spec",
                 str(ROBOTS / "nm7mar.inertia.toml"), "--plot", str(png)]) == 0
    image = matplotlib.image.imread(png)
    assert image.shape[0] > 300 and image.shape[1] > 500
    assert image[..., :3].std() > 0.05  # not a blank canvas
