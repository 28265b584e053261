"""Animations: GIF frames as the sweep says, thinning, rocking, traces, and clear refusals."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from planar import animate as anim  # noqa: E402
from planar.errors import InputError  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402


@pytest.fixture(scope="module")
def res():
    return four_bar(coupler_point=(1.7, 1.0)).sweep(np.linspace(0, 2 * np.pi, 25))


def test_gif_has_one_frame_per_pose(res, tmp_path):
    # 25 values over a whole turn: the last pose is the first again, which the looping GIF shows
    calls = []
    out = anim.animate(res, tmp_path / "fb.gif", fps=10, dpi=40, progress=lambda d, n: calls.append((d, n)))
    with Image.open(out) as im:
        assert im.n_frames == 24
        first = np.asarray(im.convert("RGB"))
        im.seek(12)
        middle = np.asarray(im.convert("RGB"))
    assert np.mean(np.any(first < 245, axis=-1)) > 0.01  # not blank
    assert np.any(first != middle)  # it moves
    assert calls[-1] == (24, 24) and len(calls) == 24


def test_frames_are_thinned_evenly_and_rock(res):
    f = anim.frame_indices(res, max_frames=10)
    assert f.tolist() == [0, 3, 6, 9, 12, 15, 18, 21]  # every third of the 24 distinct poses
    r = anim.frame_indices(res, max_frames=10, rocking=True)  # there and back: both ends shown once
    np.testing.assert_array_equal(r, np.r_[np.arange(0, 25, 3), np.arange(21, 0, -3)])
    half = four_bar().sweep(np.linspace(0, np.pi, 25))  # not a whole turn: the last pose stays
    assert anim.frame_indices(half, max_frames=12).tolist() == list(range(0, 25, 3))
    assert len(anim.frame_indices(half)) == 25
    with pytest.raises(InputError, match="max_frames must be a whole number of at least 1"):
        anim.frame_indices(half, max_frames=0)


def test_unsolved_poses_are_skipped():
    res = four_bar(4, 3, 3, 3).sweep(np.radians(np.arange(0.0, 361.0, 10.0)))
    f = anim.frame_indices(res)
    assert np.all(np.isfinite(np.asarray(res.q)[f]))
    assert len(f) < len(res)


def test_traces_reach_the_current_pose(res, tmp_path, monkeypatch):
    seen = []
    real = anim.Scene.draw

    def spy(self, ax, i=0):
        seen.append((i, [ln.get_xydata()[-1].copy() for ln in ax.lines
                         if ln.get_label() == "path of C" and len(ln.get_xdata())]))
        return real(self, ax, i)

    monkeypatch.setattr(anim.Scene, "draw", spy)
    anim.animate(res, tmp_path / "t.gif", max_frames=5, dpi=30)
    i, ends = seen[-1]
    # the trace drawn before the last frame ends where C was on the frame before it
    assert len(ends) == 1 and i == 20  # frames 0, 5, 10, 15, 20 of the 24 distinct poses
    np.testing.assert_allclose(ends[0], res.position("C")[15], atol=1e-12)


def test_refusals(res, tmp_path, monkeypatch):
    with pytest.raises(InputError, match="use a .gif or .mp4"):
        anim.animate(res, tmp_path / "x.avi")
    monkeypatch.setattr(anim, "ffmpeg_available", lambda: False)
    with pytest.raises(InputError, match="needs ffmpeg"):
        anim.animate(res, tmp_path / "x.mp4")
    nothing = four_bar(4, 3, 3, 3).sweep(np.radians(np.arange(150.0, 200.0, 10.0)))
    with pytest.raises(InputError, match="nothing to animate"):
        anim.frame_indices(nothing)


@pytest.mark.parametrize("call, message", [
    # (each a ValueError: an array's truth, and Pillow's "embedded null byte")
    (lambda r, p: anim.animate(r, p, trace=np.array([1, 0])), r"animate trace must be True or False, got array\(\[1, 0\]\)"),
    (lambda r, p: anim.animate(r, p, rocking=np.array([1, 0])), r"rocking must be True or False, got array"),
    (lambda r, p: anim.frame_indices(r, rocking=np.array([True, False])), "rocking must be True or False"),
    (lambda r, p: anim.animate(r, p.with_name("a\x00.gif")),
     r"cannot write an animation to '.*a\\x00\.gif': a file name cannot hold a NUL byte"),
    (lambda r, p: anim.animate(r, "\x00.gif"), r"'\\x00\.gif': a file name cannot hold a NUL byte .* name the file "
                                               r"without it"),
])
def test_bad_arguments_are_input_errors(res, tmp_path, call, message):
    with pytest.raises(InputError, match=message):
        call(res, tmp_path / "a.gif")


@pytest.mark.skipif(not anim.ffmpeg_available(), reason="ffmpeg is not installed")
def test_mp4_when_ffmpeg_exists(res, tmp_path):
    out = anim.animate(res, tmp_path / "fb.mp4", max_frames=6, dpi=40)
    assert out.stat().st_size > 1000
