"""The impossible cube's climb read at 128, 256 and 512 pixels: the reading must not depend on
the picture's size.

Both cubes (the development set's ``Impossible_Cube.3ds`` and the box model
:func:`meschers_igl.inverse.models.impossible_cube`) are z-buffered under the acceptance
benchmark's six lights; the start mescher's period must be within its 5% of the true depth gap.
At 128 x 128 all twelve are, and at 256 and 512 the box cube under all six lights (within 1%).
The file's cube at 256 was 30-31% short under five lights (8% under the sixth); read below.

The box cube at 256 was 39% short under lights 3 and 5, where two face orientations share the
ambient shade: the front bar passes in front of the upright bar behind it, first of its face
of the lit orientation (a boundary off its crease: an occlusion), then, past the upright's
edge ending on it (a T-junction), of its face of the shared shade, along the crease of that
face and the bar's.  At 128 px the straightened boundary's pixel steps put pieces of it off
their crease and they were cut; at 256 it straightens onto the crease and was not.  The
crossbar of the T-junction now runs the occlusion on
(:func:`meschers_igl.inverse.occlusion.crossbar_occlusions`): 0.8% short under both.

The box cube at 512 was 99.9% short under four lights: the front bar's end meets the frame
at a point where two occlusions end (the bar's face against the upright's, the frame's face
against the bar's), and a crease runs straight through from one side to the other.  At 128
and 256 a mesh edge happened to lie between the two cuts; at 512 both end on one vertex, and
cut through it the two holes beside it open into one, whose climbs cancel.  The surface is now
held whole over a pixel there (:func:`meschers_igl.inverse.cuts.keep_junctions`): 0.2% short.

What differs for the file (light 0): at 128 a hidden line runs from a junction on the upright
bar's dark side face (a vertex of its straightened edge: a pixel step under Douglas-Peucker,
whose short segment reads as an occlusion) to the notch where a front bar's face runs on into
a back bar's face of the same shade; at 256 that edge straightens to one line and the hidden
line is not found.  It is not all that is missing: added by hand at 256 (from the notch to the
upright bar, its end moved over 2 px) the start stayed 16% short, before crossbars ran on.
They cut one more true occlusion at 256 (a front bar's edge, across which the z-buffer's depth
jumps by 120 pixel widths), and the start goes from 16% to 30% short: more is missing than
the hidden line.  Starting lines from notches (an outline edge going on straight through one
shade) finds it at 128 only, and costs the box stairs two passes at 128.  What reads it: its
256 px pictures hold two 2 x 2 checkerboards (``a b / b a``) where a face's one-pixel spike
meets a face of its shade at a pixel corner; made whole along the main diagonal (the region
step :func:`meschers_igl.inverse.regions._tips_through_corners` takes for four tips only),
the start comes within 2.5% under all six lights.  Taken for every block it breaks the box
cube at 512 px under lights 3 and 5 (within 0.3% -> 20% short): there the block is the top of
the upright behind, a spike two pixels long on a bar two wide touching the corner of the bar
above, and made whole either way it joins two faces; no rule on the pixels around a block
(tips, spikes, the label with fewer pixels nearby) tells the two.  The picture is therefore
read both ways.  The lines' fit of the frame (the crease misfit) does not tell the two: it
picks the right reading at 256 (0.0177 -> 0.0174 for the file cube, 0.0125 < 0.0126 for the
box cube) and the wrong one for the file cube at 512 (0.0183 < 0.0184: 30% short under five
lights).  What does: a block made whole where the two faces belong to surfaces that part pins
them together, and the lift bends part of the figure's climb away (the file cube at 512 under
the tips' reading 30-34% short, the box cube at 512 under every block's 20% short); a block
left open where they meet costs no climb.  Of the two readings the one that climbs more (by
over 5%) is kept: the file cube at 256 and 512 6/6 (within 3.5%), the box cube unchanged.
"""

from __future__ import annotations

import pytest

NAME = "Impossible_Cube.3ds"


@pytest.fixture(scope="module")
def file_cube(development_model):
    return development_model(NAME)


@pytest.fixture(scope="module")
def box_cube():
    pytest.importorskip("pyvista")
    from meschers_igl.inverse.models import impossible_cube

    return impossible_cube()


def _climb_error(bench_start, model, k: int, res: int) -> float:
    """The start mescher's period over the true gap, less one, under the benchmark's light k."""
    from meschers_igl.inverse.metrics import figure_period

    m0, _, gap = bench_start(model, k, res)
    return figure_period(m0) / gap - 1.0


@pytest.mark.render
@pytest.mark.parametrize(
    ("k", "res"),
    [(k, res) for res in (128, 256, 512) for k in range(6)],
)
def test_file_cube_climbs_its_gap(bench_start, file_cube, k, res):
    err = _climb_error(bench_start, file_cube, k, res)
    assert abs(err) < 0.05, err


@pytest.mark.render
def test_by_the_lines_fit_alone_the_file_cube_at_512_falls_short(
    bench_start, file_cube, monkeypatch
):
    """The counterfactual: keeping the reading whose lines fit the frame better (the
    checkerboards' other reading never taken for its climb), the file cube at 512 comes 30%
    short (light 0)."""
    from meschers_igl.inverse import picture

    monkeypatch.setattr(picture, "CLIMB_MARGIN", float("inf"))
    assert _climb_error(bench_start, file_cube, 0, 512) < -0.2


@pytest.mark.render
def test_without_the_whole_blocks_reading_the_file_cube_at_256_falls_short(
    bench_start, file_cube, monkeypatch
):
    """The counterfactual: with checkerboards made whole only where four tips meet, the file
    cube at 256 comes 30% short (light 0)."""
    from meschers_igl.inverse import picture

    tips_only = picture._tips_through_corners
    monkeypatch.setattr(
        picture, "_tips_through_corners", lambda labels, every=False: tips_only(labels)
    )
    assert _climb_error(bench_start, file_cube, 0, 256) < -0.2


@pytest.mark.render
@pytest.mark.parametrize(
    ("k", "res"),
    [(k, res) for res in (128, 256, 512) for k in range(6)],
)
def test_box_cube_climbs_its_gap(bench_start, box_cube, k, res):
    err = _climb_error(bench_start, box_cube, k, res)
    assert abs(err) < 0.05, err
