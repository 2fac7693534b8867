"""What the referees need to know about a shot, read once from the engine's typed result.

The engine's `physics.Shot` lists events in time order; a jaw counts as a cushion for every
rule. Nothing here re-derives physics: first contact, cushions and pockets
are read straight off the events, final positions off `final`.
"""

from __future__ import annotations

from dataclasses import dataclass

from physics import Shot
from rules.spots import Point

CUSHION_EVENTS = ("ball_cushion", "ball_jaw")


@dataclass(frozen=True, slots=True)
class ShotFacts:
    """first_hit: the first ball the cue ball touched (None if none).
    pocketed: object balls pocketed, in the order they dropped, with their pockets.
    cue_pocketed: the cue ball fell in.
    cushion_after_contact: some ball (cue ball included) touched a cushion after first contact.
    cushioned: object balls that touched a cushion at any time during the shot.
    positions: where every ball still on the table came to rest.
    """

    first_hit: str | None
    pocketed: dict[str, str]
    cue_pocketed: bool
    cushion_after_contact: bool
    cushioned: frozenset[str]
    positions: dict[str, Point]


def read_shot(result: Shot, cue: str, before: dict[str, Point]) -> ShotFacts:
    """Digest an engine result for the shot of `cue` from the position `before`.

    Raises ValueError when the result does not account for every ball that was on the table.
    """
    final = result.final
    missing = sorted(set(before) - set(final))
    if missing:
        raise ValueError(f"engine result lacks balls: {', '.join(missing)}")
    first_hit: str | None = None
    after_contact = False
    pocketed: dict[str, str] = {}
    cushioned: set[str] = set()
    for ev in result.events:
        kind, balls = ev.type, ev.balls
        if kind == "ball_ball" and first_hit is None and cue in balls:
            first_hit = balls[1] if balls[0] == cue else balls[0]
        elif kind in CUSHION_EVENTS:
            cushioned.update(b for b in balls if b != cue)
            after_contact = after_contact or first_hit is not None
        elif kind == "ball_pocket":
            pocketed.update((b, ev.pocket or "unknown") for b in balls)
    positions = {
        b: (float(f.pos[0]), float(f.pos[1]))
        for b, f in final.items()
        if b in before and f.pos is not None
    }
    dropped = {b for b in before if final[b].pos is None}
    for b in dropped - set(pocketed):
        pocketed[b] = final[b].pocket or "unknown"
    return ShotFacts(
        first_hit=first_hit,
        pocketed={b: p for b, p in pocketed.items() if b != cue and b in dropped},
        cue_pocketed=cue in dropped,
        cushion_after_contact=after_contact,
        cushioned=frozenset(cushioned),
        positions=positions,
    )
