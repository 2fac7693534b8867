"""`billiards selfplay` and `billiards replay` print the same game."""

from __future__ import annotations

from server.cli import main


def test_selfplay_record_replays_to_the_same_lines(tmp_path, capsys):
    path = tmp_path / "game.json"
    assert main(["selfplay", "eightball", "--seed", "3", "--record", str(path)]) == 0
    played = capsys.readouterr().out.splitlines()
    assert played[0] == "eightball: P1 to break" and "winner" in played[-1]
    assert main(["replay", str(path)]) == 0
    assert capsys.readouterr().out.splitlines() == played


def test_replay_of_a_bad_record_fails_cleanly(tmp_path, capsys):
    path = tmp_path / "bad.json"
    path.write_text('{"setup": {"game": "snooker", "seed": 1}, "inputs": [{"option": "replace"}]}')
    assert main(["replay", str(path)]) == 2
    assert "not an option" in capsys.readouterr().err
    path.write_text("{not json")
    assert main(["replay", str(path)]) == 2
