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
console.log(JSON.stringify({ view: s.view, last: s.last?.version ?? null, grace: s.grace,
  replays: s.replays, seat: s.seatOf(me), turn: s.turnOf(me), shot: s.shot }));
"""

#: Reads {view, decision, outcome} on stdin; prints the decision, the outcome (if given) and
#: the score in words.
WORDS = """
import { decisionWords, outcomeWords, scoreWords } from %(words)s;
let text = "";
for await (const chunk of process.stdin) text += chunk;
const { view, decision, outcome } = JSON.parse(text);
console.log(JSON.stringify({ decision: decision ? decisionWords(view, decision) : null,
  outcome: outcome ? outcomeWords(view, outcome) : null, score: scoreWords(view) }));
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
    assert got["last"] == 4
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


def outcome_message(version: int, **changes) -> dict:
    """An OutcomeMessage of Ada's (seat 0) shot at `version`, as the channel carries it."""
    base = {"kind": "outcome", "protocol": 1, "version": version, "shot_id": f"s{version:07d}",
            "seat": 0, "input": {"strike": {"ball": "cue", "speed": 2.0, "heading": 90.0}},
            "decision": decision(pocketed=["3"]), "state": STATE, "next": NEXT, "rack": 1,
            "racks_won": [0, 0], "status": "playing", "winner": None}  # fmt: skip
    return {**base, **changes}


def test_a_new_rack_in_a_whole_view_leaves_no_last_shot_to_tell():
    # Practice: a shot, then a re-rack (or a retake, a set-up position): a view with no
    # last outcome. The status must not go on describing the shot of the rack before.
    practice = {"mode": "practice", "seats": [{"id": "p_a", "name": "Ada"}, None]}
    shot = outcome_message(4)
    reracked = table_view(version=5, **practice)
    got = node(APPLY, {"messages": [table_view(**practice), shot, reracked], "me": {"id": "p_a"}})
    assert got["last"] is None
    got = node(APPLY, {"messages": [table_view(**practice), shot], "me": {"id": "p_a"}})
    assert got["last"] == 4


def test_a_choice_is_told_who_chose_what():
    # Nine-ball: Ada pushed out, Bob (seat 1) chooses; a choice has no decision.
    view = table_view()
    for option, words in [
        ("play_again", "Bob chose to make Ada play again."),
        ("play_on", "Bob chose to play on."),
    ]:
        choice = outcome_message(5, seat=1, input={"option": option}, decision=None)
        assert node(WORDS, {"view": view, "outcome": choice})["outcome"] == words
    replace = outcome_message(5, seat=1, input={"option": "replace"}, decision=None)
    snooker = table_view(game="snooker", state={**STATE, "game": "snooker"})
    told = node(WORDS, {"view": snooker, "outcome": replace})["outcome"]
    assert told == "Bob chose to have the balls replaced and Ada play again."
    # The shot clock chose for Bob: said so, then what was chosen; at a match without a shot
    # clock, its turn limit.
    clock = {**replace, "shot_id": "clock:00000005", "input": {"option": "play_on"}}
    clocked = {**snooker, "options": {**snooker["options"], "shot_clock": 30}}
    told = node(WORDS, {"view": clocked, "outcome": clock})["outcome"]
    assert told == "Bob's shot clock ran out. Bob chose to play on."
    told = node(WORDS, {"view": snooker, "outcome": clock})["outcome"]
    assert told == "Bob's turn limit ran out. Bob chose to play on."


def test_each_game_scores_what_its_players_win():
    # Pool: the referee's scores stay 0; the score is the racks won.
    pool = table_view(racks_won=[1, 0], state={**STATE, "scores": [0, 0]})
    words = node(WORDS, {"view": pool})["score"]
    assert words.startswith("Racks won: Ada 1, Bob 0.") and "Score" not in words
    # Snooker in a race to 2: the frame's points, and the frames won.
    state = {**STATE, "game": "snooker", "scores": [12, 4]}
    snooker = table_view(game="snooker", state=state, racks_won=[0, 1])
    words = node(WORDS, {"view": snooker})["score"]
    assert "Score (points): Ada 12, Bob 4. Frames won: Ada 0, Bob 1." in words
    # Three-cushion: a game won is a game, not a rack.
    carom = table_view(game="three_cushion", state={**STATE, "game": "three_cushion"})
    won = decision(points=[1, 0], over=True, winner=0)
    got = node(WORDS, {"view": carom, "decision": won})
    assert got["decision"].endswith("Ada wins the game.")
    assert "Games won: Ada 0, Bob 0." in got["score"] and "rack" not in got["score"].lower()
