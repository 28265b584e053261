"""Mechanisms from their dimensions: stated distances assemble a rough sketch exactly (against
circle intersections written here), dyads place joints from published lengths (Jansen's leg
against a dyad-by-dyad computation), impossible dimensions name themselves, and a body's
angle is the direction of its reference line (the textbook's theta2, theta3, theta4)."""

import importlib.util
import json
import math
import re
from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

import planar
from planar import dimensions, io
from planar.errors import AssemblyError, FileFormatError, MobilityError, ModelError
from planar.mechanisms import four_bar, inverted_slider_crank, slider_crank, stephenson_six_bar
from planar.units import Units

EXAMPLES = Path(__file__).parents[1] / "examples"


def intersect(c1, r1, c2, r2, left):
    """The intersection of two circles left (or right) of the line c1 -> c2, by the cosine rule."""
    c1, c2 = np.asarray(c1, float), np.asarray(c2, float)
    d = c2 - c1
    D = math.hypot(*d)
    along = (r1**2 - r2**2 + D**2) / (2 * D)
    h = math.sqrt(r1**2 - along**2)
    u = d / D
    n = np.array([-u[1], u[0]])
    return c1 + along * u + (h if left else -h) * n


def bodies3(m):
    return m.add_body("crank"), m.add_body("coupler"), m.add_body("rocker")


def exact_four_bar(r1, r2, r3, r4, th2, left=True):
    A = r2 * np.array([math.cos(th2), math.sin(th2)])
    return A, intersect(A, r3, (r1, 0.0), r4, left)


def dimensioned_four_bar(r1, r2, r3, r4, th2, A_guess, B_guess, O4_guess=None):
    m = planar.Mechanism("four-bar")
    crank, coupler, rocker = bodies3(m)
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("A", crank, coupler, at=A_guess)
    m.add_revolute("B", coupler, rocker, at=B_guess)
    m.add_revolute("O4", rocker, m.ground, at=(r1, 0) if O4_guess is None else O4_guess)
    for a, b, r in (("O2", "A", r2), ("A", "B", r3), ("O4", "B", r4), ("O2", "O4", r1)):
        m.distance(a, b, r)
    m.drive("O2", start=th2)
    return m


# ---- angles: the direction of each body's reference line ---------------------------------------

def test_readme_four_bar_gives_the_textbook_angles_without_angle():
    m = planar.Mechanism("four-bar")
    crank, coupler, rocker = bodies3(m)
    A, B = exact_four_bar(4, 2, 3, 4, math.radians(60))
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("A", crank, coupler, at=A)
    m.add_revolute("B", coupler, rocker, at=B)
    m.add_revolute("O4", rocker, m.ground, at=(4, 0))
    m.drive("O2")
    res = m.sweep(np.radians([60.0, 90.0]))
    got = np.degrees([res.angle(b)[0] for b in ("crank", "coupler", "rocker")])
    np.testing.assert_allclose(got, [60.0, 46.080251, 103.283083], atol=1e-6)
    assert m.reference_line("rocker") == ("O4", "B")  # from the ground pivot, not in order of addition


def test_reference_line_rule_ties_by_order_points_after_joints_and_none_for_one_place():
    m = planar.Mechanism()
    arm, tip = m.add_body("arm"), m.add_body("tip")
    m.add_point("P", arm, at=(0, 5))  # a point comes after the joints however early it is added
    m.add_revolute("J", arm, tip, at=(2, 0))
    m.add_revolute("O", m.ground, arm, at=(0, 0))
    m.add_revolute("Q", tip, m.ground, at=(2, 0.0))
    assert m.reference_line("arm") == ("O", "J")
    assert m.reference_line("tip") is None  # its joints J and Q are at one place
    m.add_point("T", tip, at=(3, 1))
    assert m.reference_line("tip") == ("Q", "T")  # Q leads to the ground, J to the arm


def test_a_named_line_is_the_angle_at_every_pose():
    doc = json.loads(io.dumps(four_bar(coupler_point=(1.0, 0.5))))
    doc["bodies"][1]["line"] = ["A", "C"]
    res = io.from_dict(doc).mechanism.sweep([0.0, 1.0, 2.0])
    d = res.position("C") - res.position("A")
    np.testing.assert_allclose(res.angle("coupler"), np.arctan2(d[:, 1], d[:, 0]), atol=1e-12)


def test_a_file_holds_no_angle_its_coordinates_could_contradict():
    text = io.dumps(four_bar(start=math.radians(60), coupler_point=(1.0, 0.5)))
    assert '"angle' not in text.replace('"angle": "deg"', "")
    doc = json.loads(text)
    assert doc["drivers"] == [{"body": "crank", "start": 60}]
    # a length edited: the mechanism re-assembles, and the coupler's angle is its line A -> B
    assert doc["dimensions"][1] == {"between": ["O2", "A"], "length": 2.0}
    doc["dimensions"][1]["length"] = 1.5
    res = io.from_dict(doc).mechanism.sweep([math.radians(60)])
    A, B = res.position("A")[0], res.position("B")[0]
    np.testing.assert_allclose(B, exact_four_bar(4, 1.5, 3, 4, math.radians(60))[1], atol=1e-12)
    assert res.angle("coupler")[0] == pytest.approx(math.atan2(*(B - A)[::-1]), abs=1e-12)
    # without dimensions the coordinates are the geometry: A moved, the angles follow its lines
    del doc["dimensions"], doc["drivers"][0]["start"]
    doc["joints"][1]["at"] = [2.5, 0.0]
    res = io.from_dict(doc).mechanism.sweep([0.0])
    A, B = res.position("A")[0], res.position("B")[0]
    assert res.angle("coupler")[0] == pytest.approx(math.atan2(*(B - A)[::-1]), abs=1e-12)
    doc["bodies"][1]["angle"] = 40
    with pytest.raises(FileFormatError, match=r"bodies\[1\].angle: body 'coupler' has the reference line A -> B"):
        io.from_dict(doc)


def test_a_body_with_no_line_keeps_a_numeric_angle_in_files():
    from planar.mechanisms import slider_crank

    m = slider_crank(slide_angle=0.3)
    doc = json.loads(io.dumps(m))
    assert [b for b in doc["bodies"] if "angle" in b] == [{"name": "slider", "angle": math.degrees(0.3)}]


def test_catalogue_inputs_start_on_their_turn():
    m = four_bar(start=7.0)
    assert m.compile().u0.tolist() == [7.0]
    assert m.compile().sketch.bodies["crank"] == 7.0
    res = m.sweep([7.0, 7.1])
    assert res.ok.all() and res.angle("crank").tolist() == [7.0, 7.1]


def test_a_start_the_sketch_does_not_show_needs_dimensions():
    m = planar.Mechanism()
    crank = m.add_body("crank")
    m.add_revolute("O", m.ground, crank, at=(0, 0))
    m.add_point("P", crank, at=(1, 0))
    m.drive(body="crank", start=0.5)
    with pytest.raises(ModelError, match="driver 'crank' starts at 0.5 but the sketch has 0"):
        m.compile()
    m.distance("O", "P", 1.0)  # with the length stated, compile assembles the sketch at the start
    np.testing.assert_allclose(m.compile().sketch.position("P"), [math.cos(0.5), math.sin(0.5)], atol=1e-12)


# ---- distances: a rough sketch assembled exactly ------------------------------------------------

def test_rough_coordinates_assemble_to_the_exact_four_bar():
    th2 = math.radians(60)
    m = dimensioned_four_bar(4, 2, 3, 4, th2, A_guess=(1, 1.7), B_guess=(3.1, 3.9), O4_guess=(3.9, 0))
    sk = m.compile().sketch
    A, B = exact_four_bar(4, 2, 3, 4, th2)
    np.testing.assert_allclose(sk.position("A"), A, atol=1e-12)
    np.testing.assert_allclose(sk.position("B"), B, atol=1e-12)
    np.testing.assert_allclose(sk.position("O4"), [4, 0], atol=1e-12)  # stays on the ground line drawn
    assert sk.position("O2").tolist() == [0.0, 0.0]  # the first ground joint stays where drawn
    assert m.sketch().position("A").tolist() == [1.0, 1.7]  # the drawing itself is kept
    res = m.sweep([th2])
    np.testing.assert_allclose(np.degrees(res.angle("coupler")), [46.080251], atol=1e-6)


def test_the_assembly_mode_drawn_is_kept():
    th2 = math.radians(60)
    A, B = exact_four_bar(4, 2, 3, 4, th2, left=False)
    m = dimensioned_four_bar(4, 2, 3, 4, th2, A_guess=A + 0.05, B_guess=B + (0.1, -0.1))
    np.testing.assert_allclose(m.compile().sketch.position("B"), B, atol=1e-12)


def test_an_impossible_triangle_names_the_dimension_and_by_how_much():
    m = dimensioned_four_bar(10, 1, 1, 1, 0.0, A_guess=(1, 0.1), B_guess=(2, 0.5), O4_guess=(3, 0))
    with pytest.raises(AssemblyError, match=r"distance O2-O4 = 10 cannot hold with the others: the nearest "
                                            r"assembly has 3, 7 less than stated"):
        m.compile()


def test_a_start_out_of_reach_names_the_driver():
    # a triple rocker (4, 3, 3, 3) cannot reach 150 deg (its limit is 117.28 deg)
    m = dimensioned_four_bar(4, 3, 3, 3, math.radians(150), A_guess=(1.5, 2.6), B_guess=(4.4, 2.9))
    with pytest.raises(AssemblyError, match=r"the start of driver 'O2' cannot hold with the others: the nearest assembly has 2.04692 rad"):
        m.compile()


def test_a_joint_drawn_absurdly_far_is_reported_in_bounded_work():
    # A drawn 1e29 from O2 for a crank of 2 (with a coupler point C held by two lengths): the diagnosis's follow halves and doubles its step
    # without getting on; it stops after MAX_SOLVES Newton solves and names the driver
    doc = {"version": 1, "bodies": [{"name": "crank"}, {"name": "coupler"}, {"name": "rocker"}],
           "points": [{"name": "C", "body": "coupler", "at": [1.265877081724073, 0.8432458365518541]}],
           "joints": [{"type": "revolute", "name": "O2", "bodies": ["ground", "crank"], "at": [0, 0]},
                      {"type": "revolute", "name": "A", "bodies": ["crank", "coupler"], "at": [1e29, 0]},
                      {"type": "revolute", "name": "B", "bodies": ["coupler", "rocker"], "at": [1.25, 2.9047375096555625]},
                      {"type": "revolute", "name": "O4", "bodies": ["rocker", "ground"], "at": [4, 0]}],
           "dimensions": [{"between": ["O2", "O4"], "length": 4}, {"between": ["O2", "A"], "length": 2},
                          {"between": ["A", "B"], "length": 3}, {"between": ["O4", "B"], "length": 4},
                          {"between": ["A", "C"], "length": 1.118033988749895},
                          {"between": ["B", "C"], "length": 2.0615528128088303}],
           "drivers": [{"body": "crank", "start": 0}]}
    real, solves = dimensions._Problem.newton, []

    def newton(self, *args):
        solves.append(1)
        assert len(solves) <= 1000, "the follow does not stop"
        return real(self, *args)

    with mock.patch.object(dimensions._Problem, "newton", newton):
        with pytest.raises(AssemblyError, match=r"the start of driver 'crank' cannot hold with the others"):
            io.loads(json.dumps(doc)).mechanism.compile()


def _four_bar_with_A_drawn_at(x):
    """The catalogue four-bar's file (its four distances stated) with joint A drawn at (x, 0)."""
    d = io.to_dict(four_bar(), Units())
    next(j for j in d["joints"] if j["name"] == "A")["at"] = [x, 0.0]
    return io.from_dict(d).mechanism


def test_lengths_that_cannot_be_followed_from_the_drawing_assemble_the_way_round_in_the_mode_drawn():
    # (a fuzz of rough sketches) followed straight from this drawing the loop cannot close on the
    # way; the diagnosis then closed it the other way round and reported "the start of driver
    # 'O2' cannot hold with the others: the nearest assembly has 1.97649 rad, 0 rad less than stated"
    r, th2 = (3.4459050405163367, 0.9322952846996277, 2.11142710318898, 2.4882215970467447), 1.9764924194058082
    A_guess, B_guess, O4_guess = (2.5552110521204208, 7.753015328341022), (3.4944203827568048, 6.973945052315136), \
        (8.461391632546436, 0.0)
    sk = dimensioned_four_bar(*r, th2, A_guess, B_guess, O4_guess).compile().sketch
    d, e = np.subtract(O4_guess, A_guess), np.subtract(B_guess, A_guess)
    A, B = exact_four_bar(*r, th2, left=d[0] * e[1] - d[1] * e[0] > 0)  # B on the side of A -> O4 drawn
    np.testing.assert_allclose(sk.position("A"), A, atol=1e-12)
    np.testing.assert_allclose(sk.position("B"), B, atol=1e-12)


@pytest.mark.parametrize("x", [1e3, 1e5, 1e8])
def test_a_joint_drawn_far_past_its_place_is_refused_as_the_mirror_image(x):
    # (the file fuzz) A drawn past O4: the dimensions close only with B on the other side of
    # A -> O4 than drawn; the error said "O4-B = 4 cannot hold with the others: the nearest
    # assembly has 4, 4.06e-12 more than stated"
    with pytest.raises(AssemblyError, match="the dimensions hold together only with distance A-B = 3 and distance "
                                            "O4-B = 4 turned over from the drawing"):
        _four_bar_with_A_drawn_at(x).compile()


@pytest.mark.parametrize("x", [1e10, 1e20, 1e29])
def test_a_joint_drawn_too_far_for_double_precision_is_an_assembly_error_that_says_so(x):
    # (the file fuzz) at 1e20 the assembly's tolerance, relative to the drawing, held where the
    # sketch stood, and compile raised a MobilityError: "3 degree(s) of freedom, add 2 drivers"
    with pytest.raises(AssemblyError, match=re.escape(f"the sketch is drawn {x:.3g} across for dimensions of 4, too "
                                                      f"far from them to follow in double precision")):
        _four_bar_with_A_drawn_at(x).compile()


def _rocker_exact(size, c, s):
    """The rocker angle of four_bar(size, 1, size, 1.5) at a crank of cos c and sin s (exact
    fractions), B left of A -> O4: the circles' intersection in 60 digits."""
    with localcontext() as ctx:
        ctx.prec = 60
        dec = lambda x: Decimal(Fraction(x).numerator) / Decimal(Fraction(x).denominator)  # noqa: E731
        g, r4 = dec(size), dec(Fraction(3, 2))
        dx, dy = dec(c) - g, dec(s)  # O4 -> A
        d = (dx * dx + dy * dy).sqrt()
        a = (r4 * r4 - g * g + d * d) / (2 * d)  # the chord's foot from O4, towards A
        h = (r4 * r4 - a * a).sqrt()
        ux, uy = dx / d, dy / d
        return math.atan2(float(a * uy - h * ux), float(a * ux + h * uy))


@pytest.mark.parametrize("size", [1e6, 1e8, 3e8])
def test_a_four_bar_of_links_far_apart_in_size_moves_as_its_exact_solution(size):
    # ground and coupler of 1e8, crank 1 and rocker 1.5: its sketch was refused ("O4-B = 1.5
    # cannot hold with the others: the nearest assembly has 1.0003"), the sketch's circles met in
    # squares of 1e16, which rounded the rocker away; the rocker now follows to the rounding of
    # coordinates of 1e8 (crank angles of rational cos and sin: the reference is exact)
    cs = [(1, 0), (Fraction(3, 5), Fraction(4, 5)), (0, 1), (Fraction(-3, 5), Fraction(4, 5)), (-1, 0),
          (Fraction(-5, 13), Fraction(-12, 13)), (0, -1), (Fraction(12, 13), Fraction(-5, 13))]
    res = four_bar(size, 1.0, size, 1.5).compile().sweep([math.atan2(s, c) for c, s in cs])
    assert res.ok.all()  # (NEAR_SINGULAR: the small links' motions are 1e-8 of the size)
    th4 = np.array([_rocker_exact(size, c, s) for c, s in cs])
    err = np.abs(np.angle(np.exp(1j * (res.q[:, 8] - th4))))
    assert err.max() <= 16 * np.finfo(float).eps * size / 1.5


@pytest.mark.parametrize("size", [1e9, 1e11])
def test_a_four_bar_whose_mobility_double_precision_cannot_tell_is_refused_as_such(size):
    # the rocker's row is independent to ~0.65 / size of the others (0.6455 at the sketch), below
    # the rank test's 1e-9: the error said "2 degree(s) of freedom but 1 driver(s): add 1 driver(s)"
    with pytest.raises(MobilityError, match="cannot be told in double precision: its joints' rows are independent "
                                            "only to (.*) of its size, below 1e-09") as e:
        four_bar(size, 1.0, size, 1.5).compile()
    assert 0.6 <= float(re.search("only to (.*) of its size", str(e.value))[1]) * size <= 0.7


@pytest.mark.parametrize("size", [1e8, 1e10])
def test_a_four_bar_folded_flat_whose_mobility_double_precision_cannot_tell_is_refused_as_such(size):
    # sketched on its change point (ground and coupler 1, crank and rocker of size, folded flat):
    # the rows lose rank there, and at the poses the rank test moves to they are independent only
    # to ~1 / size; the error said "2 degree(s) of freedom but 1 driver(s): add 1 driver(s)"
    with pytest.raises(MobilityError, match="cannot be told in double precision"):
        four_bar(1.0, size, 1.0, size).compile()


@pytest.mark.parametrize("size", [1e9, 1e11])
def test_a_driver_double_precision_cannot_tell_from_the_joints_is_refused_as_such(size):
    # the inverted slider-crank's crank row is independent of the joints to 0.71 / size, below the
    # driver check's 1e-9: the error said the driver depends on the joints or sits on a dead centre
    with pytest.raises(MobilityError, match="driver 'crank' is independent of the joints and the drivers before it "
                                            f"only to {0.7071 / size:.2g} of its size at the sketch, below 1e-09: "
                                            "double precision cannot tell whether it moves the mechanism"):
        inverted_slider_crank(1 + size, size).compile()


@pytest.mark.parametrize("build, name", [
    (lambda: slider_crank(2.0, 1e13, offset=0.0), "O2-A = 2 is off by 2"),  # (the crank fell to 0, SOLVED)
    (lambda: four_bar(4.0, 1e-12, 3.0, 4.0), "O2-A = 1e-12 is off by 1e-12"),  # (the crank of 0, SOLVED)
])
def test_a_length_not_held_beside_a_far_larger_one_is_an_assembly_error(build, name):
    # each length holds to 1e-9 of itself, or to the rounding of the largest (1e-15 of it)
    with pytest.raises(AssemblyError, match=f"distance {name} where the drawing assembles: it is too small beside the "
                                            "largest dimension"):
        build().compile()


def test_a_short_length_holds_to_the_rounding_of_the_largest():
    # (a coupler point 7e-280 from A: its distance A-C held to the rounding of the links)
    res = four_bar(1.0, 1.0, 1.0, 2.0, coupler_point=(0.0, 7.277720432515598e-280), start=2.5).sweep([2.5])
    assert res.ok.all() and np.hypot(*(res.position("C") - res.position("A"))[0]) <= 1e-15 * 2.0


def test_a_design_whose_batch_assembly_holds_a_length_loosely_is_assembled_alone(monkeypatch):
    # (the batch's test is scaled by the design's size: with its iterations stopped early, A-B
    # was held to 2e-6 of itself)
    monkeypatch.setattr(planar.designs.assembly, "HELD", 1e-4)
    monkeypatch.setattr(planar.designs.assembly, "CLOSED", 1e-3)
    ab = np.array([3.4, 3.6, 3.5])
    study = planar.sweep_designs(planar.Vary(four_bar()), {"O2-A": [2.0, 2.5, 1.5], "A-B": ab}, [0.0, 1.0])
    assert study.ok.all()
    np.testing.assert_allclose(np.hypot(*(study.position("B") - study.position("A"))[:, 0].T), ab, rtol=1e-9)


def test_distance_and_dyad_refuse_points_of_different_bodies():
    m = planar.Mechanism()
    a, b = m.add_body("a"), m.add_body("b")
    m.add_revolute("O", m.ground, a, at=(0, 0))
    m.add_revolute("P", a, b, at=(1, 0))
    m.add_point("Q", b, at=(2, 0))
    with pytest.raises(ModelError, match="distance O-Q: 'O' is on .* a distance joins two joints or points of one body"):
        m.distance("O", "Q", 2.0)
    with pytest.raises(ModelError, match="'R' is placed from 'O', which is on none of its bodies"):
        m.add_point("R", b, at=planar.Dyad("O", 1.0, "Q", 1.0))
    with pytest.raises(ModelError, match="side must be 'left' or 'right'"):
        planar.Dyad("O", 1.0, "P", 1.0, side="up")
    m.distance("P", "Q", 1.0)
    with pytest.raises(ModelError, match="distance P-Q = 1 is stated already"):
        m.distance("Q", "P", 1.0)


lengths = st.floats(0.5, 5.0)


@settings(max_examples=60, deadline=None)
@given(lengths, lengths, lengths, lengths, st.floats(-math.pi, math.pi), st.booleans(),
       st.lists(st.floats(-1, 1), min_size=5, max_size=5))
@example(1.0, 1.0, 1.0, 1.0, -1.0, True, [0.0, 0.0, 0.0, 1.0, 0.0])  # a rhombus: B on O2
def test_distance_built_four_bar_equals_coordinate_built(r1, r2, r3, r4, th2, left, noise):
    A = r2 * np.array([math.cos(th2), math.sin(th2)])
    D = math.hypot(*(A - (r1, 0)))
    assume(abs(r3 - r4) + 0.05 < D < r3 + r4 - 0.05)  # assembles at th2, away from a limit
    A, B = exact_four_bar(r1, r2, r3, r4, th2, left)
    # rough guesses: a few percent of the size off
    e = 0.02 * min(r1, r2, r3, r4) * np.asarray(noise)
    m = dimensioned_four_bar(r1, r2, r3, r4, th2, A + e[:2], B + e[2:4], (r1 + e[4], 0))  # O4 on the frame line
    exact = planar.Mechanism("four-bar")
    crank, coupler, rocker = bodies3(exact)
    exact.add_revolute("O2", exact.ground, crank, at=(0, 0))
    exact.add_revolute("A", crank, coupler, at=A)
    exact.add_revolute("B", coupler, rocker, at=B)
    exact.add_revolute("O4", rocker, exact.ground, at=(r1, 0))
    exact.drive("O2")
    got, want = m.compile(), exact.compile()
    for n in ("A", "B", "O4"):
        np.testing.assert_allclose(got.sketch.position(n), want.sketch.position(n), atol=1e-10 * r1)
    turn = lambda a: (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi  # noqa: E731  (B on O2 puts an angle on +-pi)
    np.testing.assert_allclose(turn(np.subtract(list(got.sketch.bodies.values()), list(want.sketch.bodies.values()))),
                               0, atol=1e-10)
    u = th2 + np.linspace(0, 0.2, 3)
    r_got, r_want = got.sweep(u), want.sweep(u)
    np.testing.assert_array_equal(r_got.status, r_want.status)
    np.testing.assert_array_equal(np.isnan(r_got.q), np.isnan(r_want.q))
    d = np.nan_to_num(r_got.q - r_want.q)
    d[:, 2::3] = turn(d[:, 2::3])
    np.testing.assert_allclose(d, 0, atol=1e-9 * max(r1, r2, r3, r4))


# ---- files carry the dimensions ---------------------------------------------------------------

def test_editing_a_length_in_a_file_reassembles(tmp_path):
    th2 = math.radians(60)
    m = dimensioned_four_bar(4, 2, 3, 4, th2, A_guess=(1, 1.7), B_guess=(3.1, 3.9))
    path = io.save(m, tmp_path / "fb.json")
    doc = json.loads(path.read_text())
    assert {"between": ["A", "B"], "length": 3.0} in doc["dimensions"]
    assert doc["drivers"] == [{"joint": "O2", "start": pytest.approx(60.0)}]
    for d in doc["dimensions"]:
        if d["between"] == ["A", "B"]:
            d["length"] = 3.5
    path.write_text(json.dumps(doc))
    sk = io.load(path).mechanism.compile().sketch
    _, B = exact_four_bar(4, 2, 3.5, 4, th2)
    np.testing.assert_allclose(sk.position("B"), B, atol=1e-12)
    assert io.dumps(io.loads(io.dumps(m))) == io.dumps(m)


# ---- dyads: published dimensions ---------------------------------------------------------------

def load_example(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_jansen_foot_path_matches_a_dyad_by_dyad_computation():
    jansen = load_example("jansen")
    n = jansen.HOLY
    cranks = np.radians(np.arange(0.0, 361.0, 5.0))
    res = jansen.jansen_leg().sweep(cranks)
    assert res.ok.all()
    B = np.array([-n["a"], -n["l"]])
    for th, got in zip(cranks, res.position("G")):
        M = n["m"] * np.array([math.cos(th), math.sin(th)])
        C = intersect(M, n["j"], B, n["b"], left=False)      # above the line M -> B
        D = intersect(B, n["d"], C, n["e"], left=True)       # the outer corner of b-d-e
        E = intersect(M, n["k"], B, n["c"], left=True)       # below the line M -> B
        F = intersect(D, n["f"], E, n["g"], left=False)
        G = intersect(E, n["i"], F, n["h"], left=True)       # the foot, below
        np.testing.assert_allclose(got, G, atol=1e-9)
        assert C[1] > B[1] and E[1] < B[1] and D[0] < C[0] and G[1] < E[1]  # the leg's known shape
    assert res.position("G")[:, 1].min() == pytest.approx(-91.8, abs=0.1)


def test_stephenson_six_bar_from_its_numbers_equals_the_catalogue():
    th2 = 0.3
    m = planar.Mechanism("stephenson")
    crank, coupler, rocker = bodies3(m)
    link5, link6 = m.add_body("link5", angle=("C", "D")), m.add_body("link6")
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("O4", rocker, m.ground, at=(4, 0))
    m.add_revolute("O6", m.ground, link6, at=(2, 6))
    m.add_revolute("A", crank, coupler, at=1.5 * np.array([math.cos(th2), math.sin(th2)]))
    m.add_revolute("B", coupler, rocker, at=planar.Dyad("A", 4.0, "O4", 3.5, side="left"))
    m.add_revolute("C", coupler, link5, at=planar.Dyad("A", math.hypot(2, 1.5), "B", math.hypot(2, 1.5), side="left"))
    m.add_revolute("D", link5, link6, at=planar.Dyad("C", 4.0, "O6", 3.0, side="left"))
    m.drive(body="crank", start=th2)
    u = th2 + np.linspace(0, 2 * np.pi, 13)
    got, want = m.sweep(u), stephenson_six_bar(start=th2).sweep(u)
    for b in ("crank", "coupler", "rocker", "link5", "link6"):
        np.testing.assert_allclose(got.angle(b), want.angle(b), atol=1e-10)
    for p in ("C", "D"):
        np.testing.assert_allclose(got.position(p), want.position(p), atol=1e-10)


@settings(max_examples=40, deadline=None)
@given(lengths, lengths, lengths, st.floats(1.05, 3.0))
def test_a_ground_longer_than_the_rest_names_itself_and_the_shortfall(r2, r3, r4, excess):
    r1 = excess * (r2 + r3 + r4)
    m = dimensioned_four_bar(r1, r2, r3, r4, 0.0, A_guess=(r2, 0.1 * r2), B_guess=(r2 + r3, 0.2 * r3),
                             O4_guess=(r2 + r3 + r4, 0))
    with pytest.raises(AssemblyError) as err:
        m.compile()
    message = str(err.value)
    assert message.startswith(f"distance O2-O4 = {r1:.12g} cannot hold with the others: the nearest assembly has ")
    got, short = (float(s.split()[0]) for s in message.split("has ")[1].split(", ")[:2])
    assert got == pytest.approx(r2 + r3 + r4, rel=1e-4) and short == pytest.approx(r1 - (r2 + r3 + r4), rel=1e-2)
    assert "less than stated" in message


def slider_crank_from_lengths(B_guess, **drive):
    m = planar.Mechanism("slider-crank")
    crank, coupler, slider = m.add_body("crank"), m.add_body("coupler"), m.add_body("slider")
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("A", crank, coupler, at=(1.1, 1.6))
    m.add_revolute("B", coupler, slider, at=B_guess)
    m.add_prismatic("slide", m.ground, slider, at=B_guess, direction=(1, 0), origin=(0, B_guess[1]))
    m.distance("O2", "A", 2.0)
    m.distance("A", "B", 5.0)
    m.drive(**drive)
    return m.compile().sketch


def test_a_slider_stays_on_its_line_while_the_lengths_assemble():
    sk = slider_crank_from_lengths((5.8, 1.0), body="crank", start=math.radians(60))
    A = 2 * np.array([math.cos(math.radians(60)), math.sin(math.radians(60))])
    np.testing.assert_allclose(sk.position("A"), A, atol=1e-12)
    B = np.array([A[0] + math.sqrt(25 - (A[1] - 1) ** 2), 1.0])
    for n in ("B", "slide"):
        np.testing.assert_allclose(sk.position(n), B, atol=1e-12)
    # driven by the slider's travel: the crank follows
    sk = slider_crank_from_lengths((5.8, 1.0), joint="slide", start=5.0)
    np.testing.assert_allclose(sk.position("B"), [5.0, 1.0], atol=1e-12)
    assert np.hypot(*(sk.position("B") - sk.position("A"))) == pytest.approx(5.0, abs=1e-12)
    assert np.hypot(*sk.position("A")) == pytest.approx(2.0, abs=1e-12)


def test_a_length_restated_far_from_its_drawing_assembles_in_few_steps(monkeypatch):
    # (a coupler restated 1e5 times its drawing followed its length in 4,100 steps of up to 30
    # iterations each: 27 s; lengths now change by equal ratios, each step within the size asked)
    from planar import dimensions
    from planar.mechanisms import slider_crank

    calls, newton = [], dimensions._Problem.newton
    monkeypatch.setattr(dimensions._Problem, "newton", lambda p, *a, **k: calls.append(1) or newton(p, *a, **k))
    m = slider_crank()
    m.restate("A-B", 5e5)
    sk = m.compile().sketch
    assert np.hypot(*(sk.position("B") - sk.position("A"))) == pytest.approx(5e5, rel=1e-14)
    assert sk.position("B")[1] == pytest.approx(1.0, abs=1e-9) and len(calls) < 100


@pytest.mark.parametrize("length", [1e4, 1e99])
def test_a_restated_distance_that_cannot_hold_is_the_one_named(length):
    # (a restated distance is the last stated, the first suspect: 1e99 named O4-B, which
    # "cannot hold" only because A-B had outgrown it, and 1e4 took 21 s to say so)
    m = four_bar()
    m.restate("A-B", length)
    with pytest.raises(AssemblyError, match=re.escape(f"distance A-B = {length:.12g} cannot hold with the others")):
        m.compile()


def test_a_ground_line_counting_travel_from_far_away_leaves_the_mechanism_its_own_size():
    # (the line's origin 1e7 away made the sketch's size 1e7: every pose NEAR_SINGULAR, and a
    # sweep of five values took 88 s)
    m = planar.Mechanism("slider-crank")
    crank, coupler, slider = m.add_body("crank"), m.add_body("coupler"), m.add_body("slider")
    m.add_revolute("O2", m.ground, crank, at=(0, 0))
    m.add_revolute("A", crank, coupler, at=(2, 0))
    m.add_revolute("B", coupler, slider, at=(6.898979485566356, 1))
    m.add_prismatic("slide", m.ground, slider, at=(6.898979485566356, 1), direction=(1, 0), origin=(1e7, 1))
    m.drive("O2", start=0.0)
    model = m.compile()
    res = model.sweep(np.linspace(0, 2 * np.pi, 5))
    assert model.L < 10 and np.all(res.status == planar.Status.SOLVED)
    np.testing.assert_allclose(res.coordinate("slide"), res.position("B")[:, 0] - 1e7, rtol=0, atol=1e-8)


def test_a_named_point_far_away_leaves_the_mechanism_its_own_size():
    # (a point named 1e7 away on the coupler made the model's size 1e7: a sweep of five values
    # took over 25 s, every pose measured near a crossing at that scale)
    m = planar.mechanisms.four_bar(2, 5, 4, 5)
    m.add_point("far", "coupler", at=(1e7, 0))
    model = m.compile()
    res = model.sweep(np.linspace(0, 2 * np.pi, 5))
    assert model.L < 10 and np.all(res.status == planar.Status.SOLVED)
    A, B, far = res.position("A"), res.position("B"), res.position("far")
    # the point rides on the coupler: fixed along and across the line A -> B
    u = (B - A) / np.hypot(*(B - A).T)[:, None]
    d = far - A
    local = np.c_[u[:, 0] * d[:, 0] + u[:, 1] * d[:, 1], u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0]]
    assert np.hypot(*local[0]) > 9e6
    np.testing.assert_allclose(local, np.tile(local[0], (5, 1)), rtol=0, atol=1e-6)


def test_a_ground_line_drawn_through_a_point_far_along_it_leaves_the_mechanism_its_own_size():
    m = planar.Mechanism("wheel")
    wheel = m.add_body("wheel")
    m.add_rolling("roll", wheel, m.ground, 1.0, centre=(0, 1), through=(1e7, 0), direction=(1, 0))
    m.add_point("C", wheel, at=(0, 1))
    m.drive(body="wheel", start=0.0)
    model = m.compile()
    res = model.sweep(np.linspace(0, 3, 5))
    assert model.L < 10 and np.all(res.status == planar.Status.SOLVED)
    np.testing.assert_allclose(res.position("C"), np.c_[-np.linspace(0, 3, 5), np.ones(5)], rtol=0, atol=1e-12)
