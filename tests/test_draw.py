"""Figures rendered with Agg and checked for what they must show: one bar or plate per body,
hatched ground pivots, blocks, gears, racks, labels; paths where the sweep says; arrows as the
velocities are; panels one per kind of output; limit positions marked."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.patches import Circle, Polygon, Rectangle  # noqa: E402
from matplotlib.quiver import Quiver  # noqa: E402

from planar import draw  # noqa: E402
from planar.analysis.outputs import output_values  # noqa: E402
from planar.errors import InputError  # noqa: E402
from planar.joints import JOINT_TYPES, CarrierGear, Gear, Joint, RackPinion  # noqa: E402
from planar.mechanisms import CATALOGUE, four_bar, slider_crank  # noqa: E402
from planar.results import Status  # noqa: E402


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def rendered(ax):
    """The figure as an RGB array (it renders: no artist fails to draw)."""
    fig = ax.figure if not isinstance(ax, np.ndarray) else ax[0].figure
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3]


def ink(img):
    """Fraction of pixels that are not white."""
    return float(np.mean(np.any(img < 245, axis=-1)))


@pytest.fixture(scope="module")
def fb():
    return four_bar(4, 2, 3, 4, coupler_point=(1.7320508075688772, 1.0)).sweep(np.radians(np.arange(0, 361, 10.0)),
                                                                               velocity=10.0)


def thick_lines(ax):
    return [ln for ln in ax.lines if ln.get_linewidth() >= 5]


def test_four_bar_pose_has_each_part(fb):
    ax = draw.draw(fb, 6)
    # one outline per body (and a fill line inside it): crank and rocker bars, the coupler a plate
    outlines = [ln for ln in ax.lines if ln.get_linewidth() == 7.5]
    assert sorted(len(ln.get_xdata()) for ln in outlines) == [2, 2, 4]
    assert len(thick_lines(ax)) == 2 * len(outlines)
    crank = next(ln for ln in outlines if np.allclose(ln.get_xydata()[0], fb.position("O2")[6])
                 or np.allclose(ln.get_xydata()[1], fb.position("O2")[6]))
    assert {tuple(np.round(p, 9)) for p in crank.get_xydata()} == {tuple(np.round(fb.position(n)[6], 9)) for n in ("O2", "A")}
    hatched = [p for p in ax.patches if isinstance(p, Rectangle) and p.get_hatch()]
    assert len(hatched) == 2  # the two ground pivots
    triangles = [p for p in ax.patches if isinstance(p, Polygon) and len(p.get_xy()) == 4 and p.get_facecolor()[:3] == (1, 1, 1)]
    assert len(triangles) == 2
    plates = [p for p in ax.patches if isinstance(p, Polygon) and p.get_alpha() == 0.55]
    assert len(plates) == 1  # the coupler, a triangle A B C
    assert sorted(t.get_text() for t in ax.texts) == ["A", "B", "C", "O2", "O4"]
    assert "crank = 60 deg" in ax.get_title()
    assert ink(rendered(ax)) > 0.02


def test_the_pose_is_where_the_sweep_says(fb):
    ax = draw.draw(fb, 6, labels=False)
    pins = [ln for ln in ax.lines if ln.get_marker() == "o" and ln.get_markerfacecolor() == "white"]
    got = np.array(sorted(tuple(np.round(np.ravel(ln.get_xydata()), 9)) for ln in pins))
    want = np.array(sorted(tuple(np.round(fb.position(n)[6], 9)) for n in ("O2", "A", "B", "O4")))
    np.testing.assert_allclose(got, want, atol=1e-9)


def test_draw_a_model_or_mechanism_draws_the_sketch():
    m = four_bar(coupler_point=(1.0, 0.5))
    ax = draw.draw(m)
    assert len(thick_lines(ax)) == len(thick_lines(draw.draw(m.compile()))) == 6
    assert "crank = 0 deg" in ax.get_title()


def test_paths_follow_the_sweep(fb):
    ax = draw.draw_paths(fb, ["C", "B"])
    paths = [ln for ln in ax.lines if ln.get_label().startswith("path of")]
    assert [p.get_label() for p in paths] == ["path of C", "path of B"]
    np.testing.assert_array_equal(paths[0].get_xydata(), fb.position("C"))
    np.testing.assert_array_equal(paths[1].get_xydata(), fb.position("B"))


def test_default_paths_are_the_named_points_or_the_moving_joints(fb):
    assert draw.path_points(fb, None) == ["C"]
    res = four_bar().sweep(np.linspace(0, 1, 5))
    assert draw.path_points(res, None) == ["A", "B"]  # O2 and O4 do not move


def test_vectors_are_the_velocities_and_accelerations(fb):
    ax = draw.draw_vectors(fb, 6, ["A", "C"])
    qv = [c for c in ax.collections if isinstance(c, Quiver)]
    assert len(qv) == 2
    v = np.array([fb.velocity("A")[6], fb.velocity("C")[6]])
    a = np.array([fb.acceleration("A")[6], fb.acceleration("C")[6]])
    for q, want in zip(qv, (v, a)):
        got = np.stack([q.U, q.V], axis=1)
        scale = got[0, 0] / want[0, 0]
        np.testing.assert_allclose(got, want * scale, rtol=1e-12)
        assert np.max(np.hypot(*got.T)) == pytest.approx(0.25 * draw.Scene(fb).L)  # the longest: a quarter
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0].startswith("velocity: 1 length unit = ") and labels[1].startswith("acceleration")


def test_instant_centres_mark_finite_ones_and_list_those_at_infinity():
    ax = draw.draw_instant_centres({"I12": (0, 0), "I13": (2.8, 4.9), "I24": (np.inf, 0.0)})
    assert sorted(t.get_text() for t in ax.texts) == ["I12", "I13", "at infinity: I24"]
    rendered(ax)


def test_instant_centres_of_a_sweep_with_loci(fb):
    from planar.analysis import instant_centre

    ax = draw.draw_instant_centres(fb, 6, loci=True)
    labels = sorted(t.get_text() for t in ax.texts)
    assert labels == ["I12", "I13", "I14", "I23", "I24", "I34"]
    i13 = next(t for t in ax.texts if t.get_text() == "I13")
    np.testing.assert_allclose(i13.xy, instant_centre(fb, "ground", "coupler")[6])  # 2.839095, 4.917457
    loci = [ln for ln in ax.lines if ln.get_linestyle() == "-."]
    assert len(loci) == 4  # I13, I23, I24, I34 move; I12 and I14 are the ground pivots


def test_output_panels_one_per_kind(fb):
    axes = draw.plot_outputs(fb)
    assert len(axes) == 5  # angles, rates, accelerations of the bodies; speed and acceleration of C
    coupler = next(ln for ln in axes[1].lines if ln.get_label() == "coupler")
    np.testing.assert_allclose(coupler.get_ydata(), fb.omega("coupler"))
    np.testing.assert_allclose(coupler.get_xdata(), np.arange(0, 361, 10.0))
    assert axes[-1].get_xlabel() == "input crank [deg]"
    assert "[rad/s]" in axes[1].get_ylabel()
    with pytest.raises(InputError, match="needs 2 axes"):
        draw.plot_outputs(fb, ["angle:coupler", "omega:coupler"], ax=[axes[0]])
    with pytest.raises(InputError, match="unknown output 'spin:coupler'"):
        output_values(fb, "spin:coupler")


def test_slider_outputs_and_picture():
    res = slider_crank().sweep(np.linspace(0, 2 * np.pi, 25))
    outs = draw.default_outputs(res.model)
    assert {"travel:slide", "travel_rate:slide", "travel_accel:slide"} <= set(outs)
    np.testing.assert_array_equal(output_values(res, "travel:slide"), res.coordinate("slide"))
    ax = draw.draw(res, 3)
    blocks = [p for p in ax.patches if isinstance(p, Polygon) and len(p.get_xy()) == 5 and p.get_alpha() is None
              and p.get_facecolor()[3] > 0 and p.get_facecolor()[:3] != (1, 1, 1)]
    assert len(blocks) == 1
    centre = blocks[0].get_xy()[:4].mean(axis=0)
    np.testing.assert_allclose(centre, res.position("B")[3], atol=1e-12)


def test_limit_positions_are_marked_where_the_sweep_found_them():
    # a triple rocker (non-Grashof): the crank cannot turn fully; the sweep locates its limit
    res = four_bar(4, 3, 3, 3).sweep(np.radians(np.arange(0, 361, 5.0)))
    assert not res.ok.all()
    limits = [e for e in res.events if e.kind == "limit"]
    assert limits
    ax = draw.draw_paths(res, ["B"])
    marks = [ln for ln in ax.lines if ln.get_marker() == "s" and len(ln.get_xdata())]
    assert len(marks) == len(limits)
    b, s = res.model.points["B"]
    np.testing.assert_allclose(marks[0].get_xydata()[0], draw.world(np.asarray(limits[0].q), b, s), atol=1e-12)
    assert "limit position" in [t.get_text() for t in ax.get_legend().get_texts()]
    axes = draw.plot_outputs(res, ["angle:rocker"])
    assert len(axes[0].patches) >= 1  # the unassemblable inputs are shaded
    vlines = [ln for ln in axes[0].lines if ln.get_linestyle() == ":"]
    assert [ln.get_xdata()[0] for ln in vlines] == pytest.approx([np.degrees(e.input) for e in res.events])
    ax = draw.draw_event_poses(res)
    assert len(ax.lines) == 3 * len(res.events)  # a dotted outline per body at each event


def test_unsolved_pose_refuses_to_draw():
    res = four_bar(4, 3, 3, 3).sweep(np.radians(np.arange(0.0, 181.0, 10.0)))
    assert res.status[-1] == Status.NOT_ASSEMBLABLE
    with pytest.raises(InputError, match="pose 18 did not solve"):
        draw.draw(res, 18)
    with pytest.raises(InputError, match="cannot draw a list"):
        draw.draw([1, 2])


def test_every_joint_class_has_a_picture():
    for cls in JOINT_TYPES:
        if not cls.is_driver:
            assert cls.draw_part is not Joint.draw_part and cls.attach is not Joint.attach, cls.__name__


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_every_catalogue_mechanism_draws(name):
    model = CATALOGUE[name]().compile()
    span = np.where(model.input_lengths, 0.2 * model.L, 0.5)
    values = model.u0 + np.linspace(0, 1, 9)[:, None] * span
    res = model.sweep(values if len(model.drivers) > 1 else values[:, 0])
    ax = draw.draw(res, 4)
    draw.draw_paths(res, ax=ax)
    img = rendered(ax)
    assert ink(img) > 0.02
    joints = {type(j) for j in model.joints}
    if joints & {Gear, CarrierGear}:
        assert any(isinstance(p, Circle) for p in ax.patches)
    if RackPinion in joints:
        assert any(len(ln.get_xdata()) > 10 for ln in ax.lines)  # the teeth


def test_a_wheel_rolling_inside_a_ring():
    from planar.mechanisms import rolling_wheel

    res = rolling_wheel(1.0, track_radius=3.0).sweep(np.linspace(0, 3, 7))
    assert {type(j).__name__ for j in res.model.joints} == {"RollingContact"}
    ax = draw.draw(res, 3)
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    ring = [c for c in circles if c.get_hatch()]
    assert len(ring) == 1 and ring[0].get_radius() == pytest.approx(3.0 * 1.12)
    wheel = next(c for c in circles if not c.get_hatch() and c.get_radius() == pytest.approx(1.0))
    np.testing.assert_allclose(wheel.center, res.position("centre")[3], atol=1e-12)
    marks = [ln for ln in ax.lines if ln.get_marker() == "o" and ln.get_markersize() == 4]
    assert len(marks) == 1  # the wheel turns and shows it; the fixed ring has no mark


def test_the_every_joint_example_draws_all_parts():
    import runpy
    from pathlib import Path

    build = runpy.run_path(str(Path(__file__).parents[1] / "examples" / "every_joint_type.py"))["build"]
    res = build().sweep(np.linspace(0, 1, 3))
    ax = draw.draw(res, 1)
    rendered(ax)
    kinds = {type(j).__name__ for j in res.model.joints}
    assert kinds == {"Revolute", "Prismatic", "Slot", "CarrierGear", "Gear", "RackPinion"}
    assert len([p for p in ax.patches if isinstance(p, Circle)]) == 5  # gear1, gear2, planet, pinion, wheel


def test_pictures_for_many_bodies_keep_distinct_colours_and_fit_a_screen():
    from planar.mechanisms import open_chain

    res = open_chain([1.0] * 12).sweep(np.zeros((3, 12)) + np.linspace(0, 1, 3)[:, None])
    axes = draw.plot_outputs(res)
    colours = [ln.get_color() for ln in axes[0].lines if ln.get_label().startswith("link")]
    assert len(colours) == 12 and len(set(colours)) == 12
    width, height = axes[0].figure.get_size_inches()
    assert width <= 8 and height <= 9
    scene = draw.Scene(res)
    assert len({scene.colour(b) for b in range(1, 13)}) == 12
    assert len(set(draw.PATH_COLOURS)) == len(draw.PATH_COLOURS) >= 64
    assert len(set(draw.FILLS)) == len(draw.FILLS) >= 64


def _label_boxes(ax):
    ax.figure.canvas.draw()
    renderer = ax.figure.canvas.get_renderer()
    return [t.get_window_extent(renderer) for t in ax.texts if t.get_fontstyle() == "italic"]


@pytest.mark.parametrize("build", ["every_joint_type", "crowded"])
def test_point_labels_do_not_collide(build):
    if build == "every_joint_type":
        import importlib.util
        from pathlib import Path

        spec = importlib.util.spec_from_file_location(
            "every_joint_type", Path(__file__).resolve().parents[1] / "examples" / "every_joint_type.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        mech = module.build()
    else:  # named points packed closer than a label is wide
        mech = four_bar(4, 2, 3, 4)
        for k in range(6):
            mech.add_point(f"P{k}", "coupler", at=(1.2 + 0.12 * k, 1.8 + 0.05 * k))
    ax = draw.draw(mech)
    boxes = _label_boxes(ax)
    assert len(boxes) >= 6
    for k, a in enumerate(boxes):
        for b in boxes[k + 1:]:
            assert not a.overlaps(b), (a, b)


def test_a_long_sweep_draws_a_thinned_line_that_breaks_where_the_sweep_does():
    from types import SimpleNamespace

    from planar.draw.style import DRAWN, drawn
    from planar.results import Status

    N = 50 * DRAWN
    x = np.linspace(0.0, 1.0, N)
    y = np.sin(20 * x)
    y[20_000:20_500] = np.nan  # values not solved
    status = np.zeros(N, np.int8)
    status[300_001] = Status.JUMPED
    X, Y = drawn(SimpleNamespace(status=status), x, y)
    assert DRAWN // 2 < X.size <= DRAWN + 10
    # the line stops at the last value before the gap and starts again at the first after it
    i = np.flatnonzero(np.isnan(Y) & np.isfinite(X))
    assert X[i[0] - 1] == x[19_999] and X[i[-1] + 1] == x[20_500]
    # a NaN before the jump, between the values either side of it
    j = np.flatnonzero(np.isnan(X))[0]
    assert X[j - 1] == x[300_000] and X[j + 1] == x[300_001]
    assert X[0] == x[0] and X[-1] == x[-1] and np.all(np.diff(X[np.isfinite(X)]) > 0)
    # a short sweep is drawn whole
    assert drawn(SimpleNamespace(status=np.zeros(5)), np.arange(5.0))[0].tolist() == [0, 1, 2, 3, 4]


@pytest.fixture(scope="module")
def weighed():
    """A four-bar with a massive coupler under gravity, and its forces (reactions of tens)."""
    m = four_bar(coupler_point=(1.0, 0.5))
    m.set_mass("coupler", 1.0, (1.0, 1.0), 0.1)
    m.gravity = (0.0, -9.81)
    res = m.sweep(np.linspace(0.0, 1.0, 5), velocity=10.0)
    return res, res.forces()


def _axes(projection):
    return plt.figure().add_subplot(projection=projection)


BAD_DRAWING_CALLS = [
    # (call on a sweep and its forces, message): each was an AttributeError, IndexError, TypeError,
    # matplotlib's ValueError or a RuntimeWarning
    (lambda r, f: draw.input_axis(3), r"input_axis needs a sweep result .* got int"),
    (lambda r, f: draw.input_axis(r.model), r"input_axis needs a sweep result .* got Model"),
    (lambda r, f: draw.default_outputs(r), r"default_outputs needs a Model \(Mechanism.compile\(\), .* got Sweep"),
    (lambda r, f: draw.default_outputs(None), r"default_outputs needs a Model .* got NoneType"),
    (lambda r, f: draw.draw_vectors(r, 0, []), r"draw_vectors points: name one or more of \['A', .*\], got \[\]"),
    (lambda r, f: draw.draw_vectors(r, 0, scale=(1e308, 1.0)), r"draw_vectors scale 1e\+308 draws arrows beyond float64"),
    *[(lambda r, f, s=s: draw.figure(r, size=s),
       r"figure size must be \(width, height\) in inches, each from 0.5 to 50, got " + shown)
      for s, shown in [((-1, 5), r"\(-1, 5\)"), ("x", "'x'"), ((7.0,), r"\(7.0,\)"), ((np.nan, 5), r"\(nan, 5\)"),
                       (7.0, "7.0"), ((10**400, 5), r"\(1000")]],
    (lambda r, f: draw.draw_forces(f, 0, 3), r"draw_forces joints: name one or more of \['A', 'B', 'O2', 'O4'\], got \[3\]"),
    (lambda r, f: draw.draw_forces(f, 0, ["nope"]), r"draw_forces joints: name one or more of .* got \['nope'\]"),
    (lambda r, f: draw.draw_forces(f, scale=1e308), r"draw_forces scale 1e\+308 draws arrows beyond float64's largest "
                                                    r"number: give a smaller scale"),
    (lambda r, f: draw.figure(r, paths=np.array([1, 0])), r"figure paths must be True or False, got array\(\[1, 0\]\)"),
    (lambda r, f: draw.draw_paths(r, events=np.array([1, 0])), "draw_paths events must be True or False"),
    (lambda r, f: draw.draw_vectors(r, velocity=np.array([1, 0])), "draw_vectors velocity must be True or False"),
    (lambda r, f: draw.draw_instant_centres(r, loci=np.array([1, 0])), "draw_instant_centres loci must be True or False"),
    (lambda r, f: draw.plot_outputs(r, ["angle:rocker"], events=np.array([1, 0])), "plot_outputs events must be True or"),
    (lambda r, f: draw.draw(r, 0, labels=np.array([1, 0])), "draw labels must be True or False"),
    (lambda r, f: draw.draw(r, 0, ax=_axes("polar")), r"ax must be matplotlib axes of x and y .* got <PolarAxes"),
    (lambda r, f: draw.draw(r, 0, ax=_axes("3d")), r"ax must be matplotlib axes of x and y .* got <Axes3D"),
    (lambda r, f: draw.draw_paths(r, ax=_axes("polar")), r"ax must be matplotlib axes of x and y"),
    (lambda r, f: draw.plot_outputs(r, ["angle:rocker"], ax=[_axes("polar")]), r"ax must be matplotlib axes of x and y"),
]


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("call, message", BAD_DRAWING_CALLS, ids=range(len(BAD_DRAWING_CALLS)))
def test_bad_drawing_arguments_are_input_errors(weighed, call, message):
    with pytest.raises(InputError, match=message):
        call(*weighed)


@pytest.mark.filterwarnings("error")
def test_arrows_too_small_for_a_finite_default_scale_are_drawn_at_one():
    res = four_bar(coupler_point=(1.0, 0.5)).sweep(np.linspace(0.0, 1.0, 5), velocity=1e-320)
    ax = draw.draw_vectors(res, 1)
    assert "velocity: 1 length unit = 1 " in ax.get_legend_handles_labels()[1][0]
