"""web/src/play/state.js and words.js, run by Node: the client's one table state changes only by
the server's messages (a view, an outcome, a presence message), and the referee's words name
the people at the table."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from server.protocol.models import TableView

PLAY = Path(__file__).resolve().parents[2] / "web" / "src" / "play"

#: Reads {messages, me} on stdin, applies each message to a TableState and prints what it holds.
APPLY = """
import { TableState } from %(state)s;
let text = "";
for await (const chunk of process.stdin) text += chunk;
const { messages, me } = JSON.parse(text);
const s = new TableState();
for (const m of messages) s.apply(m);
console.log(JSON.stringify({ view: s.view, decided: s.decided?.version ?? null, grace: s.grace,
  replays: s.replays, seat: s.seatOf(me), turn: s.turnOf(me), shot: s.shot }));
"""

#: Reads {view, decision} on stdin; prints the decision in words.
WORDS = """
import { decisionWords, scoreWords } from %(words)s;
let text = "";
for await (const chunk of process.stdin) text += chunk;
const { view, decision } = JSON.parse(text);
console.log(JSON.stringify({ decision: decisionWords(view, decision), score: scoreWords(view) }));
"""


def node(script: str, payload: dict):
    binary = shutil.which("node")
    assert binary, "node is missing: `bash dev.sh test` installs Debian's npm (and node)"
    modules = {name: json.dumps((PLAY / f"{name}.js").as_uri()) for name in ("state", "words")}
    result = subprocess.run(
        [binary, "--input-type=module", "-e", script % modules],
        input=json.dumps(payload),
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(result.stdout)


SHOT = {"place": "anywhere", "place_required": True, "targets": ["1"], "push_out": False,
        "call": [], "nominate": []}  # fmt: skip
NEXT = {"seat": 1, "player": "p_b", "kinds": ["shot"], "cue_ball": "cue",
        "ball_in_hand": "anywhere", "options": [], "deadline": None, "shot": SHOT}  # fmt: skip
STATE = {"game": "nineball", "balls": {"1": [0.5, 1.0]}, "turn": 1, "scores": [0, 0],
         "visit": 0, "best": [0, 0]}  # fmt: skip


def table_view(**changes) -> dict:
    """A TableView as the server sends it: validated by its model, so every field is there."""
    view = {
        "id": "a" * 20, "channel": "table-t", "game": "nineball", "mode": "match",
        "options": {"race_to": 2, "shot_clock": 0, "private": False}, "status": "playing",
        "seats": [{"id": "p_a", "name": "Ada"}, {"id": "p_b", "name": "Bob"}], "version": 3,
        "rack": 1, "racks_won": [0, 0], "state": STATE, "next": None, "last_outcome": None,
        "presence": [True, True], "winner": None, "rematch": [False, False],
    }  # fmt: skip
    return TableView.model_validate({**view, **changes}).model_dump(mode="json")


def decision(**changes) -> dict:
    base = {"player": 0, "fouls": [], "points": [0, 0], "pocketed": [], "respotted": {},
            "notes": [], "next_player": 1, "ball_in_hand": None, "options": [], "over": False,
            "winner": None}  # fmt: skip
    return {**base, **changes}


def test_an_outcome_changes_the_fields_it_carries_and_nothing_else():
    after = {**STATE, "balls": {}, "turn": 0}
    outcome = {"kind": "outcome", "protocol": 1, "version": 4, "seat": 0, "decision": decision(),
               "state": after, "next": NEXT, "rack": 2, "racks_won": [1, 0], "status": "playing",
               "winner": None, "replay": "r" * 24}  # fmt: skip
    got = node(APPLY, {"messages": [table_view(), outcome], "me": {"id": "p_b"}})
    view = got["view"]
    assert (view["version"], view["state"], view["next"]) == (4, after, NEXT)
    assert (view["rack"], view["racks_won"], view["seats"][0]["name"]) == (2, [1, 0], "Ada")
    assert got["decided"] == 4
    assert got["replays"] == [{"rack": 1, "id": "r" * 24, "unfinished": False}]
    # Every rule question is the server's `next`: Bob's shot, with its ShotRules.
    assert (got["seat"], got["turn"], got["shot"]) == (1, "shot", SHOT)


def test_a_table_message_replaces_the_view_and_presence_only_presence():
    resigned = table_view(status="over", winner=1, version=5, next=None)
    presence = {"kind": "presence", "protocol": 1, "version": 5, "presence": [False, True],
                "grace_until": [100.0, None]}  # fmt: skip
    messages = [table_view(next=NEXT), {"kind": "table", "version": 5, "view": resigned}, presence]
    got = node(APPLY, {"messages": messages, "me": {"id": "p_a"}})
    assert got["view"]["status"] == "over" and got["view"]["presence"] == [False, True]
    assert got["grace"] == [100.0, None]
    assert (got["seat"], got["turn"], got["shot"]) == (0, None, None)


def test_the_referee_names_people_not_p1_and_p2():
    foul_note = {"code": "foul_warning", "text": "P2 is on 2 fouls"}
    got = node(WORDS, {"view": table_view(), "decision": decision(player=1, notes=[foul_note])})
    assert "Bob is on 2 fouls." in got["decision"]
    assert "P2" not in got["decision"]
    # Practice: one person plays both sides, and is credited by name.
    practice = table_view(mode="practice", seats=[{"id": "p_a", "name": "Ada"}, None])
    got = node(WORDS, {"view": practice, "decision": decision(player=1, notes=[foul_note])})
    assert "Ada is on 2 fouls." in got["decision"] and "P2" not in got["decision"]


def test_three_cushion_scores_points_not_pots():
    view = table_view(game="three_cushion", state={**STATE, "game": "three_cushion"})
    scored = node(WORDS, {"view": view, "decision": decision(points=[1, 0])})
    missed = node(WORDS, {"view": view, "decision": decision()})
    assert scored["decision"].startswith("Ada scored a point.")
    assert missed["decision"].startswith("Ada did not score.")
    assert "potted" not in scored["decision"] + missed["decision"]
    assert "Current run (points): 0" in scored["score"] and "Break: 0" not in scored["score"]
