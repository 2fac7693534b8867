"""`billiards selfplay` and `billiards replay` print the same game; replay refuses, with exit
status 2 and one line naming the input, a record that is not the game it states."""

from __future__ import annotations

import json

from rules.tamper import heading_last
from server.cli import main


def selfplayed(tmp_path, capsys, *args: str) -> tuple[object, list[str]]:
    path = tmp_path / "game.json"
    assert main(["selfplay", *args, "--record", str(path)]) == 0
    return path, capsys.readouterr().out.splitlines()


def test_selfplay_record_replays_to_the_same_lines(tmp_path, capsys):
    path, played = selfplayed(tmp_path, capsys, "eightball", "--seed", "3")
    assert played[0] == "eightball: P1 to break" and "winner" in played[-1]
    assert main(["replay", str(path)]) == 0
    assert capsys.readouterr().out.splitlines() == played


def test_a_share_link_replays_to_the_same_lines(tmp_path, capsys):
    assert main(["selfplay", "nineball", "--seed", "2", "--link"]) == 0
    *played, link = capsys.readouterr().out.splitlines()
    path = tmp_path / "link.txt"
    path.write_text(link)
    assert main(["replay", str(path)]) == 0
    assert capsys.readouterr().out.splitlines() == played


def test_replay_refuses_a_tampered_record_naming_the_input(tmp_path, capsys):
    from rules.record import GameRecord

    path, _ = selfplayed(tmp_path, capsys, "nineball", "--seed", "5")
    record = GameRecord.from_json(path.read_text())
    path.write_text(heading_last(record, None).to_json())
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"billiards replay: input #{len(record.inputs)}: ")


def test_replay_of_a_bad_record_fails_cleanly(tmp_path, capsys):
    path, _ = selfplayed(tmp_path, capsys, "snooker", "--seed", "1", "--max-inputs", "1")
    data = json.loads(path.read_text())
    data["inputs"] = [{"option": "replace"}]
    path.write_text(json.dumps(data))
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("billiards replay: input #1: 'replace' is not")
    for text in ("{not json", '{"setup": {"game": "snooker", "seed": 1}}', "not a link"):
        path.write_text(text)
        assert main(["replay", str(path)]) == 2
        assert len(capsys.readouterr().err.splitlines()) == 1
    path.write_bytes(b"\xff\xfe{")
    assert main(["replay", str(path)]) == 2
    assert len(capsys.readouterr().err.splitlines()) == 1
