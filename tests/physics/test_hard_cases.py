"""The hard cases of an event-based engine, each set up exactly and checked by what must hold."""

import math
from itertools import pairwise

import pytest

from physics import simulate
from physics.examples import BREAKS, nineball_break, triangle
from physics.params import CAROM, POOL
from tests.physics.probe import energy_steps, max_overlap

R = POOL.R
W, L = 1.27, 2.54


def run(balls, initial=None, models=None, params=None, table="nineball"):
    scene = {"table": table, "balls": balls, "initial": initial or {}}
    if models:
        scene["models"] = models
    if params:
        scene["params"] = params
    return simulate(scene)


def assert_sane(shot, p=POOL):
    """No overlap beyond 1e-9 m, nothing off the table, everything at rest or pocketed."""
    assert max_overlap(shot, p.R) < 1e-9
    for name, f in shot.final.items():
        assert f.state in ("stationary", "pocketed"), name
        if f.pos is not None:
            x, y = f.pos
            assert -1e-9 <= x <= W + 1e-9 and -1e-9 <= y <= L + 1e-9, name


def events_of(shot, kind):
    return [e for e in shot.events if e.type == kind]


@pytest.mark.parametrize("gap", [0.0, 1e-9])
@pytest.mark.parametrize("rack", ["nineball_break", "fifteen_ball_break"])
def test_frozen_rack_broken_at_full_speed(rack, gap):
    shot = simulate(BREAKS[rack](speed=10.0, gap=gap))
    assert_sane(shot)
    collided = {b for e in events_of(shot, "ball_ball") for b in e.balls}
    assert len(collided) == len(shot.final)  # the break reaches every ball
    assert len(events_of(shot, "ball_ball")) >= len(shot.final) - 1


def test_gap_zero_and_gap_nanometre_agree_early_on():
    """A 1e-9 m gap only delays the contacts by nanoseconds; the first contacts match."""
    a = simulate(nineball_break(gap=0.0))
    b = simulate(nineball_break(gap=1e-9))
    first_a = [(e.type, e.balls) for e in a.events[:4]]
    first_b = [(e.type, e.balls) for e in b.events[:4]]
    assert first_a == first_b
    assert abs(a.events[2].t - b.events[2].t) < 1e-6


@pytest.mark.parametrize("n", [3, 5])
def test_newtons_cradle(n):
    """Elastic, frictionless balls in a touching row pass the whole momentum down the line.

    The cue ball arrives stunned (sliding without spin) so nothing pushes after the contact."""
    row = {str(k): [W / 2, 1.0 + 2 * R * k] for k in range(n)}
    row["cue"] = [W / 2, 1.0 - 2 * R - 0.01]
    shot = run(
        row,
        initial={"cue": {"v": [0.0, 0.5], "w": [0.0, 0.0, 0.0]}},  # a stun shot
        models={"ball_ball": "frictionless"},
        params={"e_b": 1.0},
    )
    first = [e for e in events_of(shot, "ball_ball")][:n]
    # One contact after another down the line, all at the same instant.
    assert [e.balls for e in first] == [("cue", "0")] + [(str(k), str(k + 1)) for k in range(n - 1)]
    assert max(e.t for e in first) - min(e.t for e in first) < 1e-12
    last = shot.final[str(n - 1)]
    others = [shot.final[str(k)].pos[1] for k in range(n - 1)]
    # The last ball runs far; the others barely move from where they stood.
    assert last.pos is None or last.pos[1] > 1.0 + 2 * R * (n - 1) + 0.3
    assert all(abs(y - (1.0 + 2 * R * k)) < 0.02 for k, y in enumerate(others))
    assert_sane(shot)


def test_cradle_with_friction_loses_a_little_at_each_contact():
    row = {str(k): [W / 2, 1.0 + 2 * R * k] for k in range(3)}
    row["cue"] = [W / 2, 0.7]
    shot = run(row, initial={"cue": {"v": [0.0, 2.0], "w": [-2.0 / R, 0.0, 0.0]}})
    assert_sane(shot)
    assert shot.final["2"].pos is None or shot.final["2"].pos[1] > shot.final["1"].pos[1] + 0.3


def test_ball_frozen_to_cushion_hit_along_it():
    """Hit straight along the rail (of a carom table, so no pocket swallows it), a ball
    touching the cushion runs along it without a single cushion contact."""
    r = CAROM.R
    balls = {"cue": [r, 0.3], "1": [r, 0.6]}
    shot = run(
        balls,
        initial={"cue": {"v": [0.0, 1.5], "w": [-1.5 / r, 0.0, 0.0]}},
        table="three_cushion",
    )
    assert max_overlap(shot, r) < 1e-9
    assert not [e for e in events_of(shot, "ball_cushion") if e.cushion == "left"]
    assert abs(shot.final["1"].pos[0] - r) < 1e-9
    assert shot.final["1"].pos[1] > 1.0


def test_ball_frozen_to_cushion_hit_into_it():
    """Hit square into the rail with a stun shot, the frozen ball meets the cushion at once,
    comes back off it into the stopped cue ball and sends that back up the table."""
    balls = {"cue": [0.4, 1.0], "1": [R, 1.0]}
    shot = run(balls, initial={"cue": {"v": [-2.0, 0.0], "w": [0.0, 0.0, 0.0]}})
    assert_sane(shot)
    kinds = [(e.type, e.balls) for e in shot.events if e.type in ("ball_ball", "ball_cushion")]
    assert kinds[:3] == [
        ("ball_ball", ("cue", "1")),
        ("ball_cushion", ("1",)),
        ("ball_ball", ("1", "cue")),
    ]
    assert shot.events[1].t - shot.events[0].t < 1e-9
    assert shot.final["cue"].pos[0] > 0.4


def test_two_collisions_at_the_same_instant_are_symmetric():
    """The cue ball meets two balls at once: both contacts at one time, a mirror outcome."""
    d = 2 * R / math.sqrt(2)
    balls = {"cue": [W / 2, 1.0], "a": [W / 2 - d, 1.0 + d + 0.2], "b": [W / 2 + d, 1.0 + d + 0.2]}
    shot = run(
        balls,
        initial={"cue": {"v": [0.0, 2.0], "w": [0.0, 0.0, 0.0]}},
        models={"ball_ball": "frictionless"},
    )
    first, second = events_of(shot, "ball_ball")[:2]
    assert first.t == second.t
    xa, ya = shot.final["a"].pos
    xb, yb = shot.final["b"].pos
    assert abs((xa - W / 2) + (xb - W / 2)) < 1e-6 and abs(ya - yb) < 1e-6
    assert_sane(shot)


@pytest.mark.parametrize(("offset", "touches"), [(2 * R + 1e-7, False), (2 * R - 1e-7, True)])
def test_grazing_contact(offset, touches):
    """A ball passing another at a hair over or under 2R misses it or clips it."""
    balls = {"cue": [0.3, 0.5], "1": [0.3 + offset, 1.2]}
    shot = run(balls, initial={"cue": {"v": [0.0, 2.0], "w": [-2.0 / R, 0.0, 0.0]}})
    assert bool(events_of(shot, "ball_ball")) is touches
    assert_sane(shot)
    if touches:
        # A graze barely moves the object ball, and the cue ball keeps its line.
        assert abs(shot.final["1"].pos[1] - 1.2) < 0.01


def test_ball_comes_to_rest_touching_another():
    """Rolled so that it stops within a hair of another ball: at rest, no contact, no overlap."""
    p = POOL
    gap = 1e-10
    dist = 0.5
    v0 = math.sqrt(2 * p.u_r * p.g * (dist - gap))
    balls = {"cue": [0.6, 1.0], "1": [0.6, 1.0 + 2 * R + dist]}
    shot = run(balls, initial={"cue": {"v": [0.0, v0], "w": [-v0 / R, 0.0, 0.0]}})
    assert_sane(shot)
    assert not events_of(shot, "ball_ball")
    assert shot.final["cue"].pos[1] == pytest.approx(1.0 + dist - gap, abs=1e-9)


def test_ball_comes_to_rest_against_a_cushion():
    p = POOL
    dist = 0.4
    v0 = math.sqrt(2 * p.u_r * p.g * dist)
    balls = {"cue": [0.6, L - R - dist]}
    shot = run(balls, initial={"cue": {"v": [0.0, v0 * (1 + 1e-9)], "w": [-v0 / R, 0.0, 0.0]}})
    assert_sane(shot)
    # It settles against the cushion in a handful of ever-smaller contacts, then rests.
    assert shot.final["cue"].pos[1] == pytest.approx(L - R, abs=1e-9)
    assert len(shot.events) < 20


@pytest.mark.parametrize(("offset", "drops"), [(-0.034, False), (-0.033, True)])
def test_ball_rattles_in_the_jaws(offset, drops):
    """Into a deep corner pocket a little off centre, a ball bounces from jaw to jaw; a hair
    further over it rattles out, a hair less and it drops after the rattle."""
    c = 0.118 / math.sqrt(2)
    mouth = (W - c / 2 + offset / math.sqrt(2), L - c / 2 - offset / math.sqrt(2))
    start = [mouth[0] - 0.6 / math.sqrt(2), mouth[1] - 0.6 / math.sqrt(2)]
    v = 1.0 / math.sqrt(2)
    shot = run(
        {"cue": start},
        initial={"cue": {"v": [v, v], "w": [-v / R, v / R, 0.0]}},
        table={"w": W, "l": L, "corner_depth": 0.08, "corner_radius": 0.05},
    )
    jaws = [e.cushion for e in events_of(shot, "ball_jaw")]
    assert len(jaws) >= 3
    assert all(a != b for a, b in pairwise(jaws))  # side to side
    assert all(e.pocket == "top_right" for e in events_of(shot, "ball_jaw"))
    assert (shot.final["cue"].state == "pocketed") is drops
    assert_sane(shot)


@pytest.mark.parametrize("models", [{}, {"cushion": "han"}, {"spin": False}])
def test_energy_never_increases_at_an_event(models):
    steps = energy_steps(nineball_break() | {"models": models})
    assert len(steps) > 50
    for kind, before, after in steps:
        assert after <= before * (1 + 1e-12), kind


def test_carom_table_never_looks_for_pockets():
    balls = {"white": [0.3, 0.3], "red": [1.0, 2.0]}
    shot = run(
        balls,
        initial={"white": {"v": [3.0, 3.0], "w": [0.0, 0.0, 0.0]}},
        table="three_cushion",
    )
    assert not events_of(shot, "ball_pocket") and not events_of(shot, "ball_jaw")
    assert all(f.state == "stationary" for f in shot.final.values())


def test_corner_hit_is_two_cushion_contacts():
    """Into the corner of a carom table: both cushions, one after the other, at one instant."""
    x = 0.5
    balls = {"white": [x, x]}
    shot = run(
        balls,
        initial={"white": {"v": [-2.0, -2.0], "w": [0.0, 0.0, 0.0]}},
        table="three_cushion",
        models={"spin": False},
    )
    rails = events_of(shot, "ball_cushion")
    assert {rails[0].cushion, rails[1].cushion} == {"left", "bottom"}
    assert rails[1].t - rails[0].t < 1e-12


def test_triangle_is_frozen():
    pts = triangle((0.5, 1.0), 5, R)
    dists = [math.dist(a, b) for k, a in enumerate(pts) for b in pts[k + 1 :]]
    assert min(dists) == pytest.approx(2 * R, abs=1e-15)


def test_touching_balls_moving_apart_never_collide():
    """Frozen together and sent apart (one rolling away, one sliding back): no contact."""
    balls = {"a": [0.6, 1.0], "b": [0.6, 1.0 + 2 * R]}
    shot = run(
        balls,
        initial={
            "a": {"v": [0.0, -1.0], "w": [1.0 / R, 0.0, 0.0]},
            "b": {"v": [0.0, 0.5], "w": [0.0, 0.0, 0.0]},
        },
    )
    assert not events_of(shot, "ball_ball")
    assert_sane(shot)


def test_dead_balls_pressed_together_do_not_sink_into_each_other():
    """e_b = 0: a ball sliding sideways beside one rolling into it, touching with no relative
    normal speed. Each resting contact used to come REST_DEPTH deeper than the last, 134 events
    and 1.2e-8 m of overlap; now the slides finish at the first and the pair parts cleanly."""
    a = [1.0231897584744567, 1.058332074728651]
    nx, ny = 0.1501284127919044, -0.9886665057907967  # a to b, touching
    b = [a[0] + 2 * R * nx / math.hypot(nx, ny), a[1] + 2 * R * ny / math.hypot(nx, ny)]
    shot = run(
        {"a": a, "b": b},
        initial={
            "a": {"v": [-0.47866, -0.97213], "w": [-20.3484, 211.3631, 48.4789]},
            "b": {"v": [-0.64866, -0.99794], "w": [-10.3418, -6.8085, -54.4959]},
        },
        params={"mathavan_steps": 1, "u_s": 0.1204, "e_b": 0.0},
        table={"w": 1.27, "l": 1.27},
    )
    assert max_overlap(shot, R) < 1e-9
    assert len(shot.events) < 30


@pytest.mark.parametrize("cushion", ["han", "mathavan"])
def test_a_dead_cushion_does_not_let_a_pressing_ball_sink_in(cushion):
    """e_c = 0: a ball flush with a rail, spinning into it as it runs along. Each resting contact
    used to sink REST_DEPTH deeper than the last (56 events, 1.006e-9 m into the cushion)."""
    r = CAROM.R
    w, l = 1.42, 2.84
    shot = run(
        {"b": [w - r, 0.54]},
        initial={"b": {"v": [0.66, 1.2], "w": [490.0, 98.0, 12.0]}},
        models={"cushion": cushion},
        params={"f_c": 0.0, "e_c": 0.0},
        table="three_cushion",
    )
    deepest = max(
        max(x - (w - r), r - x, y - (l - r), r - y)
        for x, y in (shot.position("b", e.t) for e in shot.events)
    )
    assert deepest < 2e-10  # one REST_DEPTH at most
    assert len(shot.events) < 15


@pytest.mark.parametrize("spin", [True, False])
def test_a_crawl_below_the_rest_speed_leaves_the_ball_where_it_is(spin):
    """A ball set moving at 1e-10 m/s (at the engine's rest threshold) against a frozen
    neighbour is at rest: it neither creeps on at constant speed while another ball runs for
    seconds nor presses into its neighbour."""
    balls = {"a": [1.0, 1.0], "b": [1.0 + 2 * R, 1.0], "c": [R, 0.5]}
    initial = {"a": {"v": [1e-10, 0.0], "w": [0, 0, 0]}, "c": {"v": [2.0, 0.0], "w": [0, 0, 0]}}
    shot = run(balls, initial, models={"spin": spin})
    assert shot.duration > 1.0
    assert shot.final["a"].pos == (1.0, 1.0)
    assert all(seg.v == (0.0, 0.0) for seg in shot.trajectories["a"])
    assert_sane(shot)


#: Issue 9's wedge: a ball flush with the left rail of the nine-ball table, touching another.
WEDGED = {"b0": [R, 1.0], "b1": [0.08344873188206842, 0.9840314042779313]}


@pytest.mark.parametrize("w", [[1.0, 0.0, 0.0], [1.0, 0.0, -2.0]])
@pytest.mark.parametrize("e_c", [POOL.e_c, 0.0])
def test_a_ball_wedged_by_its_spin_settles_at_once(w, e_c):
    """A stationary ball whose spin drives it into a cushion and a neighbour at once. Resolved
    one contact at a time it bounced between them with ever-tinier steps: 498 events, with
    side spin past the budget (2,000 events), with a dead cushion 2.6e-9 m past the cushion
    line. Settled jointly, it rolls off along the rail pushing the neighbour away."""
    shot = run(WEDGED, initial={"b0": {"v": [0.0, 0.0], "w": w}}, params={"e_c": e_c})
    assert len(shot.events) < 10
    assert_sane(shot)
    nearest = min(shot.position("b0", e.t)[0] for e in shot.events)
    assert min(nearest, shot.final["b0"].pos[0]) >= R - 2e-10  # one REST_DEPTH at most
    assert shot.final["b0"].pos[1] < 1.0 - 1e-6  # it moved down the rail, as the spin drives it
    assert math.dist(shot.final["b1"].pos, WEDGED["b1"]) > 1e-6  # and pushed the neighbour


@pytest.mark.parametrize("angle", [0.0, 0.3, 0.7, 1.2])
@pytest.mark.parametrize("models", [{}, {"spin": False, "ball_ball": "frictionless"}])
def test_a_dead_ball_driven_into_a_wedge_settles_at_once(angle, models):
    """e_b = 0: a ball rolled into a neighbour that touches a ball flush with the rail. Dead
    collisions one pair at a time passed the push down the chain and back with ever-tinier
    steps (20-362 events); a collision too dead to part the pair is settled with the cluster."""
    nx, ny = math.cos(angle), math.sin(angle)
    wedged = [R + 2 * R * nx, 1.0 + 2 * R * ny]
    start = [wedged[0] + 0.3, wedged[1] + 0.05]
    dx, dy = wedged[0] - start[0], wedged[1] - start[1]
    vx, vy = 2.0 * dx / math.hypot(dx, dy), 2.0 * dy / math.hypot(dx, dy)
    shot = run(
        {"b0": [R, 1.0], "b1": wedged, "c": start},
        initial={"c": {"v": [vx, vy], "w": [-vy / R, vx / R, 0.0]}},
        models=models,
        params={"e_b": 0.0},
    )
    assert len(shot.events) < 20
    assert_sane(shot)
    on_table = [pos for pos in (shot.position("b0", e.t) for e in shot.events) if pos]
    assert min(x for x, _ in on_table) >= R - 2e-10  # pushed along the rail, perhaps to a pocket
