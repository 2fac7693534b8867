"""The event loop: from one event to the next, never stepping through the time in between.

Each ball carries a snapshot (time, position, velocity, spin) and the constant accelerations
of its motion state, so its position at any later time before its next event is closed-form
(physics.motion). After every event only the balls it touched are re-examined: their next
motion transition, cushion, jaw and pocket contacts, and their pairings with every other ball
(physics.roots gives each first contact). Predictions go into a heap with the versions of the
balls they were computed from; a prediction whose ball has changed since is dropped when it
surfaces. So a stationary ball costs no more than a distance test until something moves
towards it, a pair that cannot meet within both balls' current paths is culled by that bound
before any polynomial is formed, and a carom table never looks for pockets (it has none).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from heapq import heappop, heappush

from physics import motion, records, roots
from physics.ball_ball import BALL_BALL_MODELS
from physics.cushion import CUSHION_MODELS
from physics.motion import POCKETED, ROLLING, SLIDING, SPINNING, STATIONARY
from physics.scene import CONTACT_TOLERANCE, Scene
from physics.tables import Geometry, Jaw, Pocket, Segment
from physics.trajectory import ModelsUsed, Shot

#: A contact within this gap (m) is a touching contact, decided at the present.
TOUCH_GAP = 1e-11
#: A ball touching another ball or a cushion and not approaching it, and not coming apart
#: either, makes a new contact once it presses in this much deeper (m): rolling along a
#: cushion or beside a frozen ball is no contact at all, and a ball pressed in by friction is
#: caught well inside the 1e-9 m the engine promises.
REST_DEPTH = 1e-10
#: A touching ball approaching slower than this (m/s) is not approaching: float noise of a
#: tangent contact is not a new contact (a slow real push is caught through REST_DEPTH).
MIN_APPROACH = 1e-9
#: Approach speeds below this (m/s) are a resting contact: resolved without rebound, which
#: stops the endless ever-smaller bounces of a ball pressed against another ball or a cushion.
REST_SPEED = 1e-4
#: A ball within this gap (m) of another ball or a cushion touches it, for settling a cluster
#: of resting contacts jointly (the scene format's own tolerance for touching).
CLUSTER_GAP = CONTACT_TOLERANCE
#: The largest cluster of resting contacts settled in one step: a ball wedged between a
#: cushion and a neighbour is two balls and two contacts, a ball in a corner of a frozen rack
#: a few more. Contacts past the bound are left to events of their own; the bound keeps the
#: exact joint solution (a search over the 2^contacts sets of contacts that push) cheap.
CLUSTER_BALLS = 4
CLUSTER_CONTACTS = 5
#: Tolerance (m/s) of the joint solution: an approach this slow is none, an impulse this
#: small in the wrong direction is nil (float noise of an exact solution).
LCP_TOL = 1e-12
#: The budget of one shot, which ends a runaway shot (a scene built to burn a server core) with
#: `BudgetExceeded` at a bounded cost: at most MAX_EVENTS events, and at most MAX_WORK units of
#: work, since the work of an event grows with the balls on the table and a cushion impact can
#: cost a thousand integration steps. A contact test (a ball against another ball or a jaw or
#: pocket circle: the chord test and, where that cannot cull, a quartic) is one unit, a step
#: of Mathavan's cushion integration CUSHION_STEP_WORK units (their costs are in that ratio).
#: Real shots stay far inside both: a full-power break makes 80-250 events and 3,000-12,000
#: units. At the budget a shot has cost about 120 ms on one core of the development machine
#: (bench/adversarial.py).
MAX_EVENTS = 2_000
MAX_WORK = 40_000
CUSHION_STEP_WORK = 2
#: A jaw, pocket or other ball farther from a moving ball than the two can close in before the
#: path's horizon is culled by its distance alone (see _table_contact and _predict_pair) where
#: its squared distance exceeds the squared reach by this fraction: far beyond any rounding
#: in either that test or the chord test it stands in for.
FAR_MARGIN = 1e-6


class SimulationError(RuntimeError):
    """The engine could not finish a shot (a bug, or a scene far outside play)."""


class BudgetExceeded(SimulationError):
    """A shot went past the engine's budget (MAX_EVENTS, MAX_WORK) and was abandoned."""


class _Ball:
    __slots__ = (
        "ax",
        "ay",
        "dw",
        "name",
        "pocket",
        "segments",
        "state",
        "t0",
        "t_own",
        "version",
        "vx",
        "vy",
        "w",
        "x",
        "y",
    )

    def __init__(self, name: str, x: float, y: float) -> None:
        self.name = name
        self.t0 = 0.0
        self.x, self.y = x, y
        self.vx = self.vy = self.ax = self.ay = 0.0
        self.w = (0.0, 0.0, 0.0)
        self.dw = (0.0, 0.0, 0.0)
        self.state = STATIONARY
        self.version = 0
        self.t_own = math.inf  # the ball's next own event: its path holds until then
        self.pocket: str | None = None
        self.segments: list[tuple] = []

    def at(self, t: float) -> tuple[float, float, float, float]:
        """Position and velocity at time t (no change to the snapshot)."""
        dt = t - self.t0
        return (
            self.x + (self.vx + 0.5 * self.ax * dt) * dt,
            self.y + (self.vy + 0.5 * self.ay * dt) * dt,
            self.vx + self.ax * dt,
            self.vy + self.ay * dt,
        )

    def advance(self, t: float) -> None:
        """Move the snapshot to time t."""
        dt = t - self.t0
        if dt:
            self.x, self.y, self.vx, self.vy = self.at(t)
            w, dw = self.w, self.dw
            self.w = (w[0] + dw[0] * dt, w[1] + dw[1] * dt, w[2] + dw[2] * dt)
            self.t0 = t


class Simulation:
    """One shot on one table. `run()` returns the Shot; the object is used once."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.p = scene.params
        #: The constants of the balls' motion, read from the params once (physics.motion).
        self.consts = motion.Constants(scene.params)
        self.models = scene.models
        self.spin = scene.models.spin
        self.ball_ball = BALL_BALL_MODELS[
            "frictionless" if not self.spin else scene.models.ball_ball
        ]
        self.cushion: Callable = CUSHION_MODELS[scene.models.cushion]
        self.sin_theta = scene.sin_theta
        self.geometry = g = scene.geometry
        R = scene.params.R
        self.diameter = 2.0 * R  # where two balls' centres meet
        self.rails, self.circles = _unpacked(g, R)
        self.balls = [_Ball(name, x, y) for name, (x, y) in scene.positions.items()]
        self.index = {b.name: k for k, b in enumerate(self.balls)}
        self.heap: list[tuple] = []
        self.seq = 0
        self.now = 0.0
        #: The events so far, as records (physics.records builds the Shot's models at the end).
        self.events: list[records.EventRecord] = []
        #: What the shot cost: possible contacts with balls and round things (jaws, pockets)
        #: looked at, and how many of those were not culled and needed a quartic solved.
        self.contacts_checked = 0
        self.quartics_solved = 0
        #: Integration steps the cushion model took, in a list it adds to (see physics.cushion).
        self.cushion_steps = [0]

    def work(self) -> int:
        """The work done so far, in the units of MAX_WORK."""
        return self.contacts_checked + CUSHION_STEP_WORK * self.cushion_steps[0]

    # -- state changes -------------------------------------------------------------------

    def _set_motion(self, b: _Ball, v: tuple[float, float], w: tuple[float, float, float]) -> None:
        """Give ball b a new velocity and spin at the present and choose its motion state."""
        consts = self.consts
        if not self.spin:
            w = motion.rolling_spin(v, 0.0, consts.R)
        state = motion.classify(v, w, consts)
        if state in (STATIONARY, SPINNING):
            # Below EPS_SPEED the ball is at rest: a leftover crawl (say 1e-10 m/s) kept in its
            # segment would carry it on at constant speed with no event to stop it.
            v, w = (0.0, 0.0), (0.0, 0.0, w[2] if state == SPINNING else 0.0)
        b.t0 = self.now
        b.vx, b.vy = v
        b.w = w
        b.state = state
        b.ax, b.ay, dwx, dwy, dwz = motion.accelerations(b.state, v, w, consts)
        b.dw = (dwx, dwy, dwz)
        b.version += 1
        self._record(b)

    def _record(self, b: _Ball) -> None:
        b.segments.append((b.t0, b.state, b.x, b.y, b.vx, b.vy, b.ax, b.ay, b.w, b.dw))

    def _emit(
        self,
        kind: str,
        balls: tuple[str, ...],
        cushion: str | None = None,
        pocket: str | None = None,
    ) -> None:
        self.events.append((self.now, kind, balls, cushion, pocket))

    # -- prediction ----------------------------------------------------------------------

    def _push(self, t: float, kind: str, i: int, j: int = -1, data: object = None) -> None:
        bi = self.balls[i]
        vj = 0
        if j >= 0:
            bj = self.balls[j]
            vj = bj.version
        heappush(self.heap, (t, self.seq, kind, i, j, bi.version, vj, data))
        self.seq += 1

    def _predict(self, changed: tuple[int, ...]) -> None:
        """Queue the next events of the balls whose motion just changed.

        First each one's next event of its own, which bounds how long its path holds, then
        its next contact with every other ball (each pair once).
        """
        for i in changed:
            self._predict_own(i)
        balls = self.balls
        for k, i in enumerate(changed):
            bi = balls[i]
            earlier = changed[:k]
            for j, other in enumerate(balls):
                if j != i and other.state != POCKETED and j not in earlier:
                    self._predict_pair(i, j, bi, other)

    def _predict_own(self, i: int) -> None:
        """Queue ball i's next event of its own.

        Of its own events (motion transition, cushion, jaw, pocket) only the earliest matters:
        it changes the ball's path, and everything is predicted again then. That time also
        bounds the search for the others, which is what makes the distance culling bite.
        """
        b = self.balls[i]
        consts, now, state = self.consts, self.now, b.state
        b.t_own = math.inf
        if state not in (SLIDING, ROLLING, SPINNING):
            return
        t = now + motion.transition_time(state, (b.vx, b.vy), b.w, consts)
        kind, data = "motion", None
        if state != SPINNING:  # (a spinning ball stays where it is: its path holds for ever)
            contact = self._table_contact(b, t - now)
            if contact[0] < t:
                t, kind, data = contact
            t_spin = now + motion.spin_stop_time(b.w, consts)
            if t_spin < t:
                self._push(t_spin, "spin", i)
            b.t_own = t
        self._push(t, kind, i, -1, data)

    def _table_contact(self, b: _Ball, horizon: float) -> tuple[float, str, object]:
        """The earliest cushion, jaw or pocket contact of a moving ball within `horizon`."""
        R, now = self.consts.R, self.now
        best: tuple[float, str, object] = (math.inf, "", None)
        x, y, vx, vy, ax, ay = b.x, b.y, b.vx, b.vy, b.ax, b.ay
        speed, accel = math.hypot(vx, vy), math.hypot(ax, ay)
        for rail in self.rails:
            px, py, nx, ny = rail.px, rail.py, rail.nx, rail.ny
            g0 = (x - px) * nx + (y - py) * ny - R
            if g0 > (speed + 0.5 * accel * horizon) * horizon:
                continue
            g1 = vx * nx + vy * ny
            c2 = 0.5 * (ax * nx + ay * ny)
            if g0 <= TOUCH_GAP:
                approaching = g1 < -MIN_APPROACH
                t = (
                    0.0
                    if approaching
                    else roots.first_return((g0, g1, c2, 0.0, 0.0), horizon, REST_DEPTH)
                )
            else:
                t = roots.first_entry_quadratic(g0, g1, c2, horizon)
            if t == math.inf:  # no contact
                continue
            # Does the contact fall on this segment, not on the line beyond it?
            cx = x + (vx + 0.5 * ax * t) * t - px
            cy = y + (vy + 0.5 * ay * t) * t - py
            tx, ty = rail.tx, rail.ty
            s = (cx * tx + cy * ty) / (tx * tx + ty * ty)
            if 0.0 <= s <= 1.0:
                horizon = t
                best = (now + t, "cushion", rail.segment)
        # The chord test of _contact_time (roots.path_misses) culls a circle whose distance from
        # the ball's path, a chord less its sag |a| h^2 / 8, exceeds its radius; every point of
        # the chord is within (|v| + |a| h / 2) h of the ball. So a circle farther than its
        # radius and (|v| + 5/8 |a| h) h is culled by that test too: culled here by a distance,
        # and counted as looked at all the same.
        reach = (speed + 0.625 * accel * horizon) * horizon
        for circle in self.circles:
            dx, dy = x - circle.cx, y - circle.cy
            far = circle.radius + reach
            if dx * dx + dy * dy > far * far * (1.0 + FAR_MARGIN):
                self.contacts_checked += 1
                continue
            t = self._contact_time(dx, dy, vx, vy, ax, ay, circle.radius, horizon)
            if t != math.inf:
                horizon = t
                best = (now + t, circle.kind, circle.piece)
        return best

    def _predict_pair(self, i: int, j: int, bi: _Ball, bj: _Ball) -> None:
        if bi.state not in (SLIDING, ROLLING) and bj.state not in (SLIDING, ROLLING):
            return
        now = self.now
        xj, yj, vxj, vyj = bj.at(now)
        dx, dy, dvx, dvy = xj - bi.x, yj - bi.y, vxj - bi.vx, vyj - bi.vy
        dax, day = bj.ax - bi.ax, bj.ay - bi.ay
        horizon = min(bi.t_own, bj.t_own) - now
        # As for a circle in _table_contact, with the relative motion's reach bounded by the
        # sums of its components' sizes, which take no square roots.
        reach = (abs(dvx) + abs(dvy) + 0.625 * (abs(dax) + abs(day)) * horizon) * horizon
        far = self.diameter + reach
        if dx * dx + dy * dy > far * far * (1.0 + FAR_MARGIN):
            self.contacts_checked += 1
            return
        t = self._contact_time(dx, dy, dvx, dvy, dax, day, self.diameter, horizon)
        if t != math.inf:
            self._push(now + t, "ball", i, j)

    def _contact_time(self, dx, dy, vx, vy, ax, ay, contact, horizon) -> float:
        """When d(t) = d + v t + a t^2 / 2 first comes within `contact` of the origin (inf:
        not within `horizon`).

        (A ball's centre relative to a circle's, or one ball's relative to another's.) The
        chord test culls most candidates; the rest solve f = |d|^2 - contact^2, a quartic.
        """
        self.contacts_checked += 1
        if roots.path_misses(dx, dy, vx, vy, ax, ay, horizon, contact):
            return math.inf
        self.quartics_solved += 1
        c = (
            dx * dx + dy * dy - contact * contact,
            2.0 * (dx * vx + dy * vy),
            vx * vx + vy * vy + dx * ax + dy * ay,
            vx * ax + vy * ay,
            0.25 * (ax * ax + ay * ay),
        )
        return _first_contact(c, math.hypot(dx, dy) - contact, contact, horizon)

    # -- resolution ----------------------------------------------------------------------

    def _collide_balls(self, i: int, j: int) -> None:
        bi, bj = self.balls[i], self.balls[j]
        bi.advance(self.now)
        bj.advance(self.now)
        dx, dy = bj.x - bi.x, bj.y - bi.y
        d = math.hypot(dx, dy)
        nx, ny = dx / d, dy / d
        n = (nx, ny)
        va, wa, vb, wb = (bi.vx, bi.vy), bi.w, (bj.vx, bj.vy), bj.w
        vn = (bi.vx - bj.vx) * nx + (bi.vy - bj.vy) * ny
        if vn < REST_SPEED or self.p.e_b * vn < REST_SPEED:
            changed = self._settle((i, j), (0, 1, nx, ny))
            if changed is not None:
                self._emit("ball_ball", (bi.name, bj.name))
                self._predict(changed)
                return
            if vn < REST_SPEED:
                va, wa, vb, wb = self._rest(va, wa, vb, wb, n)
            else:
                va, wa, vb, wb = self.ball_ball(va, wa, vb, wb, n, self.p)
        else:
            va, wa, vb, wb = self.ball_ball(va, wa, vb, wb, n, self.p)
        self._set_motion(bi, va, wa)
        self._set_motion(bj, vb, wb)
        self._emit("ball_ball", (bi.name, bj.name))
        self._predict((i, j))

    def _collide_cushion(
        self, i: int, normal: tuple[float, float], kind: str, cushion: str, pocket: str | None
    ) -> None:
        b = self.balls[i]
        b.advance(self.now)
        nx, ny = normal
        vx, vy = b.vx, b.vy
        v = (vx, vy)
        vn_in = -(vx * nx + vy * ny)
        if vn_in < REST_SPEED:
            changed = self._settle((i,), (0, -1, -nx, -ny))
            if changed is not None:
                self._emit(kind, (b.name,), cushion, pocket)
                self._predict(changed)
                return
        if self.spin:
            v_new, w_new = self.cushion(v, b.w, normal, self.p, self.sin_theta, self.cushion_steps)
        else:
            vn = vx * nx + vy * ny
            k = (1.0 + self.p.e_c) * vn
            v_new, w_new = (vx - k * nx, vy - k * ny), b.w
        if vn_in < REST_SPEED:
            # Resting against the cushion: no rebound, and a slide that presses the ball into
            # the cushion is finished at once (as between two balls, see _rest).
            vn_out = v_new[0] * nx + v_new[1] * ny
            v_new = (v_new[0] - vn_out * nx, v_new[1] - vn_out * ny)
            (ax, ay), state = self._accel(v_new, w_new)
            if state == SLIDING and ax * nx + ay * ny < 0.0:
                v_new, w_new = self._finish_slide(v_new, w_new)
                # The roll a slide ends in may still run into the cushion: the cushion takes
                # that too, as a resting contact takes no rebound. Left to a real impact, a dead
                # cushion (e_c = 0) would hand back a slide pressing in again, and each round
                # would sink REST_DEPTH deeper.
                vn_out = v_new[0] * nx + v_new[1] * ny
                if vn_out < 0.0:
                    v_new = (v_new[0] - vn_out * nx, v_new[1] - vn_out * ny)
                    w_new = motion.rolling_spin(v_new, w_new[2], self.consts.R)
        self._set_motion(b, v_new, w_new)
        self._emit(kind, (b.name,), cushion, pocket)
        self._predict((i,))

    def _settle(self, seeds, first):
        """Settle a cluster of resting contacts in one step; None where there is no cluster.

        A ball pressed against a cushion and a neighbour at once (or into a few frozen
        neighbours), resolved one contact at a time, pushes itself into the other contact at
        each step: a storm of ever-closer events. Here the contact of the event (`first`,
        between seeds) and every resting contact the cluster around it touches are resolved
        together: one perfectly inelastic impulse per contact so that no contact approaches
        (_project), a slide that friction presses into any contact finished at once and the
        impulses found again (as _rest does for a pair), and a rolling ball that would catch
        up with the neighbour it follows slowed to stay clear of it (_spare). Each step only
        dissipates energy. Returns the balls whose motion was set again.
        """
        members, v, w, contacts = self._cluster(seeds, first)
        if len(contacts) < 2:
            return None
        before = list(zip(v, w, strict=True))
        v, w = self._project(v, w, contacts)
        for _ in range(CLUSTER_BALLS + 1):  # each round leaves one more ball rolling
            pressed = self._pressed_slides(v, w, contacts)
            if not pressed:
                break
            for k in pressed:
                v[k], w[k] = self._finish_slide(v[k], w[k])
            v, w = self._project(v, w, contacts)
        self._spare(v, w, contacts)
        changed = []
        for k, i in enumerate(members):
            if k < len(seeds) or (v[k], w[k]) != before[k]:
                b = self.balls[i]
                b.advance(self.now)
                self._set_motion(b, v[k], w[k])
                changed.append(i)
        return tuple(changed)

    def _cluster(self, seeds, first):
        """The balls and resting contacts around a resting contact, within the cluster bounds.

        Returns the members (ball indices, the seeds first), their velocities and spins now,
        and the contacts as (a, b, nx, ny): members a and b (b = -1 for a cushion or jaw),
        n the unit normal from a into b. A contact is resting when its approach is slower
        than REST_SPEED: a faster one is a real collision, an event of its own.
        """
        members = list(seeds)
        pos, v, w = [], [], []
        for i in members:
            self._take(i, pos, v, w)
        contacts = [first]
        k = 0
        while k < len(members) and len(contacts) < CLUSTER_CONTACTS:
            self._touching(k, members, pos, v, w, contacts)
            k += 1
        return members, v, w, contacts

    def _take(self, i, pos, v, w):
        """Add ball i's position, velocity and spin now to the lists."""
        b = self.balls[i]
        x, y, vx, vy = b.at(self.now)
        dt = self.now - b.t0
        pos.append((x, y))
        v.append((vx, vy))
        w.append((b.w[0] + b.dw[0] * dt, b.w[1] + b.dw[1] * dt, b.w[2] + b.dw[2] * dt))

    def _touching(self, k, members, pos, v, w, contacts):
        """Add member k's resting contacts not yet in `contacts` (and their balls to members)."""
        R = self.consts.R
        x, y = pos[k]
        vx, vy = v[k]
        fixed = [(nx, ny) for a, b, nx, ny in contacts if a == k and b < 0]
        for rail in self.rails:
            px, py, nx, ny, tx, ty = rail.px, rail.py, rail.nx, rail.ny, rail.tx, rail.ty
            gap = (x - px) * nx + (y - py) * ny - R
            s = ((x - px) * tx + (y - py) * ty) / (tx * tx + ty * ty)
            if abs(gap) <= CLUSTER_GAP and 0.0 <= s <= 1.0:
                self._add_fixed(k, -nx, -ny, vx, vy, fixed, contacts)
        for circle in self.circles:
            cx, cy = circle.cx, circle.cy
            d = math.hypot(x - cx, y - cy)
            if circle.kind == "jaw" and abs(d - circle.radius) <= CLUSTER_GAP:
                self._add_fixed(k, (cx - x) / d, (cy - y) / d, vx, vy, fixed, contacts)
        for i, other in enumerate(self.balls):
            if (
                other.state == POCKETED
                or i in members[: k + 1]
                or len(contacts) >= CLUSTER_CONTACTS
            ):
                continue
            self.contacts_checked += 1
            xo, yo, vxo, vyo = other.at(self.now)
            d = math.hypot(xo - x, yo - y)
            if d - 2.0 * R > CLUSTER_GAP:
                continue
            n = ((xo - x) / d, (yo - y) / d)
            if (vx - vxo) * n[0] + (vy - vyo) * n[1] >= REST_SPEED:
                continue
            if i in members:
                m = members.index(i)
                if any({a, b} == {k, m} for a, b, _, _ in contacts):
                    continue
            elif len(members) < CLUSTER_BALLS:
                m = len(members)
                members.append(i)
                self._take(i, pos, v, w)
            else:
                continue
            contacts.append((k, m, n[0], n[1]))

    def _add_fixed(self, k, nx, ny, vx, vy, fixed, contacts):
        """Add a resting contact of member k with a cushion or jaw (normal n into it), unless
        it is one already there (the normals in `fixed`, which n joins) or there is no room."""
        new = all(nx * fx + ny * fy < 1.0 - 1e-9 for fx, fy in fixed)
        if new and len(contacts) < CLUSTER_CONTACTS and vx * nx + vy * ny < REST_SPEED:
            contacts.append((k, -1, nx, ny))
        fixed.append((nx, ny))

    def _project(self, v, w, contacts):
        """The velocities after one perfectly inelastic impulse per contact, found jointly.

        The impulses lam >= 0 (per unit mass) leave no contact approaching, and push only
        where a contact would otherwise approach: the linear complementarity problem of
        inelastic contact, solved exactly by trying each set of pushing contacts in turn (a
        cluster has at most CLUSTER_CONTACTS). The result is the velocities nearest the
        present ones (in the energy's metric) that no contact approaches, so the energy never
        grows. A rolling ball weighs 7/5 m and stays rolling, as in _merge.
        """
        consts = self.consts
        inv = [
            5.0 / 7.0 if motion.classify(v[k], w[k], consts) == ROLLING else 1.0
            for k in range(len(v))
        ]
        u = [_approach(v, c) for c in contacts]
        m = len(contacts)
        A = [[_coupling(c, e, inv) for e in contacts] for c in contacts]
        lam = None
        for mask in range(1 << m):
            lam = _solve(A, u, [k for k in range(m) if mask >> k & 1])
            if lam is not None:
                break
        if lam is None:  # no set fits (a degenerate cluster): stop every member, at a loss
            return [(0.0, 0.0)] * len(v), [(0.0, 0.0, s[2]) for s in w]
        v = list(v)
        w = list(w)
        pushed = []
        for (a, b, nx, ny), impulse in zip(contacts, lam, strict=True):
            if impulse:
                v[a] = (v[a][0] - impulse * inv[a] * nx, v[a][1] - impulse * inv[a] * ny)
                pushed.append(a)
                if b >= 0:
                    v[b] = (v[b][0] + impulse * inv[b] * nx, v[b][1] + impulse * inv[b] * ny)
                    pushed.append(b)
        for k in pushed:
            if inv[k] != 1.0:
                w[k] = motion.rolling_spin(v[k], w[k][2], consts.R)
        return v, w

    def _pressed_slides(self, v, w, contacts):
        """The members whose sliding friction presses them into a contact they rest on."""
        pressed = []
        for a, b, nx, ny in contacts:
            if _approach(v, (a, b, nx, ny)) <= -REST_SPEED:
                continue  # parting: not held
            for k, sign in ((a, 1.0), (b, -1.0)):
                if k >= 0 and k not in pressed:
                    (ax, ay), state = self._accel(v[k], w[k])
                    if state == SLIDING and sign * (ax * nx + ay * ny) > 0.0:
                        pressed.append(k)
        return sorted(pressed)

    def _spare(self, v, w, contacts):
        """Slow each rolling ball that would catch up with the neighbour it follows.

        Two rolling balls touching, neither approaching, both decelerate at u_r g along their
        own velocities: the one behind (whose velocity has the larger part along the contact
        normal) would press into the one ahead again, and each new contact would come
        REST_DEPTH deeper. It gives up speed (keeping its direction, so it stays clear of a
        cushion it rolls along) until it stays clear of the other while both roll and after
        either stops: with c and c_l the cosines of the two velocities with the normal (the
        follower's towards, the leader's away) and V_l the leader's speed, its speed at most
        V_l sqrt(c_l / c) and 2 c_l V_l / (c + c_l). A leader at rest stops it.
        """
        consts = self.consts
        for a, b, nx, ny in contacts:
            if b < 0 or _approach(v, (a, b, nx, ny)) <= -REST_SPEED:
                continue
            sa, sb = math.hypot(v[a][0], v[a][1]), math.hypot(v[b][0], v[b][1])
            ca = (v[a][0] * nx + v[a][1] * ny) / sa if sa > 0.0 else 0.0
            cb = -(v[b][0] * nx + v[b][1] * ny) / sb if sb > 0.0 else 0.0
            f, c, lead, speed, c_l = (
                (a, ca, b, sb, -cb) if sa * ca >= sb * cb else (b, cb, a, sa, -ca)
            )
            state_l = motion.classify(v[lead], w[lead], consts)
            if c <= 0.0 or state_l == SLIDING or motion.classify(v[f], w[f], consts) != ROLLING:
                continue
            top = 0.0
            if state_l == ROLLING and c_l > 0.0:
                top = min(speed * math.sqrt(c_l / c), 2.0 * c_l * speed / (c + c_l))
            now = math.hypot(v[f][0], v[f][1])
            if top < now:
                v[f] = (v[f][0] * (top / now), v[f][1] * (top / now))
                w[f] = motion.rolling_spin(v[f], w[f][2], consts.R)

    def _rest(self, va, wa, vb, wb, n):
        """Two balls meeting at a crawl, which friction would keep pressing together.

        An event engine would resolve that as endless ever-smaller collisions. Instead, with
        the velocities from before the contact (at under REST_SPEED the friction impulse is
        nil): no rebound, the pair merging its normal velocities as an inelastic pair (a
        rolling ball weighs 7/5 m there, as the cloth keeps it rolling); a ball that sliding
        friction presses into the other finishes its slide at once (so the push becomes one
        real collision), and so does a slide beside a roll that slows into it (else each new
        contact would come REST_DEPTH deeper than the last); a collision that would not part
        them (dead balls, e_b near 0) is merged rather than played; and where rolling
        resistance alone presses them together (their
        paths converge by mm/s^2), the ball behind gives up just enough of its approach to
        stay clear until either ball stops. Every step only dissipates energy.
        """
        p, consts = self.p, self.consts
        va, wa, vb, wb = self._merge(va, wa, vb, wb, n)
        (aa, sa), (ab, sb) = self._accel(va, wa), self._accel(vb, wb)
        if sa == SLIDING and aa[0] * n[0] + aa[1] * n[1] > 0.0:
            va, wa = self._finish_slide(va, wa)
        if sb == SLIDING and ab[0] * n[0] + ab[1] * n[1] < 0.0:
            vb, wb = self._finish_slide(vb, wb)
        approach = (va[0] - vb[0]) * n[0] + (va[1] - vb[1]) * n[1]
        if approach >= REST_SPEED and p.e_b * approach >= REST_SPEED:
            # Now truly approaching: a real collision follows at once and parts them. (One that
            # would not part them, dead balls, is merged below instead: it would leave them
            # pressing, and each round would sink REST_DEPTH deeper.)
            return va, wa, vb, wb
        va, wa, vb, wb = self._merge(va, wa, vb, wb, n)
        (aa, sa), (ab, sb) = self._accel(va, wa), self._accel(vb, wb)
        pressing = (aa[0] - ab[0]) * n[0] + (aa[1] - ab[1]) * n[1]
        if pressing > 0.0 and SLIDING in (sa, sb):
            # Still pressed together (a slide sideways beside a roll slowing down): the slides
            # finish now too, or each new contact would sink REST_DEPTH deeper until they end.
            if sa == SLIDING:
                va, wa = self._finish_slide(va, wa)
            if sb == SLIDING:
                vb, wb = self._finish_slide(vb, wb)
            va, wa, vb, wb = self._merge(va, wa, vb, wb, n)
            (aa, sa), (ab, sb) = self._accel(va, wa), self._accel(vb, wb)
            pressing = (aa[0] - ab[0]) * n[0] + (aa[1] - ab[1]) * n[1]
        if pressing <= 0.0 or SLIDING in (sa, sb):
            return va, wa, vb, wb
        until = min(
            motion.transition_time(sa, va, wa, consts), motion.transition_time(sb, vb, wb, consts)
        )
        if not math.isfinite(until):
            return va, wa, vb, wb
        dv = 0.5 * pressing * until
        slower_a = (va[0] - dv * n[0], va[1] - dv * n[1])
        slower_b = (vb[0] + dv * n[0], vb[1] + dv * n[1])
        if sa == ROLLING and math.hypot(slower_a[0], slower_a[1]) < math.hypot(va[0], va[1]):
            va, wa = slower_a, motion.rolling_spin(slower_a, wa[2], consts.R)
        elif sb == ROLLING and math.hypot(slower_b[0], slower_b[1]) < math.hypot(vb[0], vb[1]):
            vb, wb = slower_b, motion.rolling_spin(slower_b, wb[2], consts.R)
        return va, wa, vb, wb

    def _merge(self, va, wa, vb, wb, n):
        """A perfectly inelastic normal impulse between two balls; rolling ones stay rolling."""
        consts = self.consts
        roll_a = motion.classify(va, wa, consts) == ROLLING
        roll_b = motion.classify(vb, wb, consts) == ROLLING
        ka, kb = (1.4 if roll_a else 1.0), (1.4 if roll_b else 1.0)
        na = va[0] * n[0] + va[1] * n[1]
        nb = vb[0] * n[0] + vb[1] * n[1]
        common = (ka * na + kb * nb) / (ka + kb)
        va = (va[0] + (common - na) * n[0], va[1] + (common - na) * n[1])
        vb = (vb[0] + (common - nb) * n[0], vb[1] + (common - nb) * n[1])
        if roll_a:
            wa = motion.rolling_spin(va, wa[2], consts.R)
        if roll_b:
            wb = motion.rolling_spin(vb, wb[2], consts.R)
        return va, wa, vb, wb

    def _accel(self, v, w):
        """(acceleration, state) a ball would have with this velocity and spin."""
        state = motion.classify(v, w, self.consts)
        a = motion.accelerations(state, v, w, self.consts)
        return (a[0], a[1]), state

    def _finish_slide(self, v, w):
        """The velocity and spin a sliding ball would roll with once its slide is over.

        Friction keeps the slip's direction and takes 2/7 of it off the velocity by the time
        the slip is gone; jumping to that end state only dissipates energy, as the slide does.
        """
        ux, uy = motion.slip(v, w, self.consts.R)
        v_end = (v[0] - 2.0 / 7.0 * ux, v[1] - 2.0 / 7.0 * uy)
        return v_end, motion.rolling_spin(v_end, w[2], self.consts.R)

    def _transition(self, i: int) -> None:
        b = self.balls[i]
        b.advance(self.now)
        before = b.state
        if before == SPINNING:
            # The path does not change (the ball stays where it is): no new predictions.
            b.state, b.w, b.dw = STATIONARY, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
            self._record(b)
            self._emit("spinning_stationary", (b.name,))
            return
        if before == SLIDING:
            v = (b.vx, b.vy)
            self._set_motion(b, v, motion.rolling_spin(v, b.w[2], self.consts.R))
            self._emit("sliding_rolling", (b.name,))
        if b.state != ROLLING or before == ROLLING:
            # A roll ends at rest (a slide can end at rest directly: then both events).
            self._set_motion(b, (0.0, 0.0), (0.0, 0.0, b.w[2]))
            self._emit(f"rolling_{b.state}", (b.name,))
        self._predict((i,))

    def _spin_stop(self, i: int) -> None:
        """w_z reached zero mid-path: a new output segment, the same path, no event."""
        b = self.balls[i]
        b.advance(self.now)
        b.w = (b.w[0], b.w[1], 0.0)
        b.dw = (b.dw[0], b.dw[1], 0.0)
        self._record(b)

    def _pocket(self, i: int, name: str) -> None:
        b = self.balls[i]
        b.advance(self.now)
        b.state = POCKETED
        b.pocket = name
        b.vx = b.vy = b.ax = b.ay = 0.0
        b.w = b.dw = (0.0, 0.0, 0.0)
        b.t_own = math.inf
        b.version += 1
        self._record(b)
        self._emit("ball_pocket", (b.name,), None, name)

    # -- the loop ------------------------------------------------------------------------

    def _start(self) -> None:
        scene = self.scene
        for b in self.balls:
            self._record(b)
        moving = []
        if scene.strike is not None and scene.strike_motion is not None:
            k = self.index[scene.strike.ball]
            self._set_motion(self.balls[k], scene.strike_motion.v, scene.strike_motion.w)
            self._emit("strike", (scene.strike.ball,))
            moving.append(k)
        for name, m in scene.initial.items():
            k = self.index[name]
            self._set_motion(self.balls[k], m.v, m.w)
            moving.append(k)
        self._predict(tuple(moving))

    def run(self) -> Shot:
        """Simulate the shot to its end, every ball at rest or pocketed (the cyclic garbage
        collector paused meanwhile, see records.PausedCollector)."""
        with records.PausedCollector():
            self._start()
            self._loop()
            events, trajectories, final, duration, models = self._records()
            return records.shot(events, trajectories, final, duration, models)

    def run_records(self) -> records.ShotRecord:
        """As `run`, the Shot as its records (what a batch's workers send back)."""
        with records.PausedCollector():
            self._start()
            self._loop()
            return self._records()

    def _loop(self) -> None:
        heap, balls = self.heap, self.balls
        count = 0
        while heap:
            t, _, kind, i, j, vi, vj, data = heappop(heap)
            b = balls[i]
            if b.version != vi or (j >= 0 and balls[j].version != vj):
                continue
            count += 1
            if count > MAX_EVENTS or self.work() > MAX_WORK:
                raise BudgetExceeded(
                    f"the shot went past the engine's budget ({MAX_EVENTS} events, "
                    f"{MAX_WORK} units of work) and was abandoned"
                )
            self.now = t
            if kind == "ball":
                self._collide_balls(i, j)
            elif kind == "motion":
                self._transition(i)
            elif kind == "spin":
                self._spin_stop(i)
            elif kind == "cushion":
                self._collide_cushion(i, data.normal, "ball_cushion", data.name, None)
            elif kind == "jaw":
                b.advance(t)
                dx, dy = b.x - data.center[0], b.y - data.center[1]
                d = math.hypot(dx, dy)
                self._collide_cushion(i, (dx / d, dy / d), "ball_jaw", data.name, data.pocket)
            else:
                self._pocket(i, data.name)

    def _records(self) -> records.ShotRecord:
        end = self.now
        final = {}
        trajectories = {}
        for b in self.balls:
            if b.state != POCKETED:
                b.advance(end)
            final[b.name] = (None if b.state == POCKETED else (b.x, b.y), b.state, b.pocket)
            trajectories[b.name] = b.segments
        models = _models_used(
            self.models.ball_ball, self.models.cushion, self.spin, self.geometry.spec.cushion_height
        )
        return self.events, trajectories, final, end, models


class _Rail:
    """A cushion segment as the contact search reads it: its start p, its inward normal n and
    the vector t from its start to its end, as numbers (C doubles in the kernel, where a
    tuple's items are Python floats to unpack)."""

    __slots__ = ("nx", "ny", "px", "py", "segment", "tx", "ty")

    def __init__(self, s: Segment) -> None:
        self.segment = s
        self.px, self.py = s.p1[0], s.p1[1]
        self.nx, self.ny = s.normal[0], s.normal[1]
        self.tx, self.ty = s.p2[0] - s.p1[0], s.p2[1] - s.p1[1]


class _Circle:
    """A jaw or a pocket as the contact search reads it: its centre c and the distance from it
    at which a ball's centre meets it (see _Rail)."""

    __slots__ = ("cx", "cy", "kind", "piece", "radius")

    def __init__(self, kind: str, piece: Jaw | Pocket, radius: float) -> None:
        self.kind, self.piece = kind, piece
        self.cx, self.cy = piece.center[0], piece.center[1]
        self.radius = radius


#: The tables unpacked so far (see _unpacked), by the geometry's identity and the ball radius.
_TABLES: dict[tuple[int, float], tuple[Geometry, list[_Rail], list[_Circle]]] = {}
#: How many _TABLES holds at most: a process plays on a few tables (presets, a few custom).
_TABLES_KEPT = 64


def _unpacked(g: Geometry, R: float) -> tuple[list[_Rail], list[_Circle]]:
    """The table as the contact search reads it (and never changes): each cushion segment with
    its start, normal and direction; each jaw (its circle grown by R, which is where a ball's
    centre meets it) and pocket with its centre and contact radius.

    Unpacked once per table and ball radius rather than once per shot, where it cost a short
    shot 6% of its time. A table's Geometry is one object per process for the same
    numbers (physics.tables), held by the entry so that its identity is not reused.
    """
    key = (id(g), R)
    entry = _TABLES.get(key)
    if entry is None or entry[0] is not g:
        rails = [_Rail(s) for s in g.segments]
        circles = [_Circle("jaw", c, c.radius + R) for c in g.jaws]
        circles += [_Circle("pocket", c, c.radius + 0.0) for c in g.pockets]
        if len(_TABLES) >= _TABLES_KEPT:
            _TABLES.clear()
        entry = _TABLES[key] = (g, rails, circles)
    return entry[1], entry[2]


#: The ModelsUsed of the shots so far, by their fields: each shot that used the same models
#: on a table of the same cushion height gets the same (frozen) one, where validating a new
#: one cost a short shot 2% of its time.
_MODELS_USED: dict[tuple[str, str, bool, float], ModelsUsed] = {}


def _models_used(ball_ball: str, cushion: str, spin: bool, cushion_height: float) -> ModelsUsed:
    key = (ball_ball, cushion, spin, cushion_height)
    models = _MODELS_USED.get(key)
    if models is None:
        if len(_MODELS_USED) >= _TABLES_KEPT:
            _MODELS_USED.clear()
        models = _MODELS_USED[key] = ModelsUsed(
            ball_ball=ball_ball, cushion=cushion, spin=spin, cushion_height=cushion_height
        )
    return models


def _first_contact(c: roots.Poly, gap: float, contact: float, horizon: float) -> float:
    """First contact time from now for f = |d|^2 - contact^2 with coefficients c (inf:
    none within `horizon`)."""
    if gap <= TOUCH_GAP:
        if c[1] < -2.0 * contact * MIN_APPROACH:
            return 0.0  # touching and approaching: now
        return roots.first_return(c, horizon, 2.0 * contact * REST_DEPTH)
    return roots.first_entry(c, horizon)


def _approach(v: list, contact: tuple) -> float:
    """How fast the two sides of a contact (a, b, nx, ny) close in (b = -1: a cushion)."""
    a, b, nx, ny = contact
    vx, vy = v[a]
    if b >= 0:
        vx, vy = vx - v[b][0], vy - v[b][1]
    return vx * nx + vy * ny


def _coupling(c: tuple, e: tuple, inv: list) -> float:
    """How much a unit impulse at contact e slows the approach at contact c."""
    total = 0.0
    for k, sign_c in ((c[0], 1.0), (c[1], -1.0)):
        if k < 0:
            continue
        for m, sign_e in ((e[0], 1.0), (e[1], -1.0)):
            if m == k:
                total += sign_c * sign_e * inv[k]
    return total * (c[2] * e[2] + c[3] * e[3])


def _solve(A: list, u: list, push: list) -> list | None:
    """The impulses when exactly the contacts in `push` push, or None if they do not fit.

    They fit when the pushing contacts end with no approach and impulses >= 0, and the others
    are not approaching: a solution of the inelastic contact problem. Gaussian elimination
    with partial pivoting on the pushing contacts' rows; a singular set does not fit.
    """
    n = len(push)
    rows = [[A[r][c] for c in push] + [u[r]] for r in push]
    for col in range(n):
        best = col
        for r in range(col + 1, n):
            if abs(rows[r][col]) > abs(rows[best][col]):
                best = r
        if abs(rows[best][col]) <= 1e-12:
            return None
        rows[col], rows[best] = rows[best], rows[col]
        for r in range(col + 1, n):
            f = rows[r][col] / rows[col][col]
            for c in range(col, n + 1):
                rows[r][c] -= f * rows[col][c]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        known = 0.0
        for c in range(r + 1, n):  # a loop, not sum(): Python 3.12's sum of floats compensates
            known += rows[r][c] * x[c]
        x[r] = (rows[r][n] - known) / rows[r][r]
    lam = [0.0] * len(u)
    for k, r in enumerate(push):
        if x[k] < -LCP_TOL:
            return None
        lam[r] = max(x[k], 0.0)
    for r in range(len(u)):
        if r not in push:
            pushed = 0.0
            for c in range(len(u)):
                pushed += A[r][c] * lam[c]
            after = u[r] - pushed
            if after > LCP_TOL:
                return None
    return lam
