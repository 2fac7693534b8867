"""web/src/net/protocol.js is what server/protocol/ids.py says, to the letter and in behaviour."""

from __future__ import annotations

import json
import re
import subprocess

from pydantic import BaseModel

from server.protocol import ids, models
from server.protocol.javascript import TARGET, module_text

SAMPLES = ["Ada", " Ada", "Ada ", "A.da-1_", "<b>", "a" * 24, "clock:00000001", "shot-0001", ""]


def test_the_module_in_the_tree_is_the_generated_one() -> None:
    assert TARGET.read_text() == module_text(), "run: python -m server.protocol.javascript"


def test_every_message_model_takes_its_kind_from_the_protocols_ids() -> None:
    """The kinds the browser switches on are the models' own: no message is published with a
    kind that the generated module does not name."""
    kinds = {
        model.model_fields["kind"].default
        for model in vars(models).values()
        if isinstance(model, type) and issubclass(model, BaseModel) and "kind" in model.model_fields
    }
    assert kinds == set(ids.MessageKind)
    assert all(isinstance(kind, ids.MessageKind) for kind in kinds)


def test_the_browser_reads_every_identifier_as_python_does() -> None:
    script = (
        f"import('{TARGET.as_uri()}').then((m) => console.log(JSON.stringify({{"
        "games: m.GAMES, lobby: m.LOBBY, kinds: m.KIND, table: m.tableChannel('t1'),"
        " player: m.playerChannel('p1'),"
        f" names: {json.dumps(SAMPLES)}.map((s) => m.NAME_PATTERN.test(s)),"
        f" shots: {json.dumps(SAMPLES)}.map((s) => m.SHOT_ID_PATTERN.test(s)),"
        "})))"
    )
    seen = json.loads(subprocess.run(["node", "-e", script], capture_output=True, check=True,
                                     text=True).stdout)  # fmt: skip
    assert seen == {
        "games": list(ids.GAMES),
        "lobby": ids.LOBBY,
        "kinds": {kind.name: kind.value for kind in ids.MessageKind},
        "table": ids.table_channel("t1"),
        "player": ids.player_channel("p1"),
        "names": [re.fullmatch(ids.NAME_PATTERN.strip("^$"), s) is not None for s in SAMPLES],
        "shots": [re.fullmatch(ids.SHOT_ID_PATTERN.strip("^$"), s) is not None for s in SAMPLES],
    }
