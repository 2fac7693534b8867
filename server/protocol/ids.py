"""Every identifier of the game's protocol, defined once: game names, id and name formats,
channel names, the quick-message set, timings and limits a client must know.

The wire models (server/protocol/models.py), the HTTP routes (server/http/api.py), the game
service and the command-line client read them from here, and the browser client from
`web/src/net/protocol.js`, which `server.protocol.javascript` writes from this module (a test
fails when the two differ). Nothing else writes these literals.
"""

from __future__ import annotations

import hashlib
import secrets
from enum import StrEnum

from rules.racks import POOL_GAMES, Game
from rules.spots import POOL_SIZES, STANDARD_SIZE
from rules.three_cushion import DEFAULT_TARGET

#: The format version of channel messages; bumped when a client must change to read them.
PROTOCOL = 1

# ----- games ----------------------------------------------------------------------------------
#: The games a table plays, as the API names them.
GAMES: tuple[str, ...] = tuple(game.value for game in Game)


class BotName(StrEnum):
    """The server's opponents: the rules' simple shot picker, or the searching bot at a level
    from 1 (a beginner) to 5 (the strongest), as `rules.bot.chooser` names them."""

    PICKER = "picker"
    LEVEL_1 = "bot:1"
    LEVEL_2 = "bot:2"
    LEVEL_3 = "bot:3"
    LEVEL_4 = "bot:4"
    LEVEL_5 = "bot:5"


#: Each bot's level (0: the simple shot picker, which never searches) and its name in words
#: ("Club": the club bot).
BOT_LEVELS: dict[BotName, tuple[int, str]] = {
    BotName.PICKER: (0, "Simple"),
    BotName.LEVEL_1: (1, "Beginner"),
    BotName.LEVEL_2: (2, "Casual"),
    BotName.LEVEL_3: (3, "Club"),
    BotName.LEVEL_4: (4, "Strong"),
    BotName.LEVEL_5: (5, "Strongest"),
}


class QuickText(StrEnum):
    """The fixed set of quick messages: nothing else can be said, so nothing to moderate."""

    GOOD_SHOT = "good_shot"
    GOOD_GAME = "good_game"
    NICE_TRY = "nice_try"
    WELL_PLAYED = "well_played"
    THANKS = "thanks"
    OOPS = "oops"
    HELLO = "hello"
    BYE = "bye"


# ----- ids and names --------------------------------------------------------------------------
def _whole(core: str) -> str:
    """A pattern matching `core` whole (JSON Schema's and pydantic's `$` is the very end)."""
    return f"^{core}$"


#: A display name: letters, digits, `_`, `-`, `.` and inner spaces (nothing a page could take
#: for markup), at least one letter or digit, at most `NAME_MAX` characters. (Before, `..` was
#: a name: its profile link `/player/..` opened the home page, and as every name of separators
#: alone reads as the same empty skeleton, it took all of them.)
NAME_CORE = r"[_.\-]*[A-Za-z0-9](?:[A-Za-z0-9_. \-]*[A-Za-z0-9_.\-])?"
NAME_PATTERN = _whole(NAME_CORE)
NAME_MAX = 24
#: The same in words, for the people whose name is refused.
NAME_RULE = (
    f"1 to {NAME_MAX} letters, digits, spaces, '_', '-' or '.', with a letter or digit, not"
    " starting or ending with a space"
)

TABLE_ID_CORE = r"[0-9a-f]{20}"
TABLE_ID_PATTERN = _whole(TABLE_ID_CORE)
REPLAY_ID_CORE = r"[0-9a-f]{24}"
REPLAY_ID_PATTERN = _whole(REPLAY_ID_CORE)
PLAYER_ID_CORE = r"p_[0-9a-f]{16}"
PLAYER_ID_PATTERN = _whole(PLAYER_ID_CORE)
CHALLENGE_ID_CORE = r"c_[0-9a-f]{16}"
#: A recorded real shot's id (`/api/real-shots/{id}`): the recording's own number.
REAL_SHOT_ID_CORE = r"[0-9]{1,6}"
#: A client's shot id. It holds no `:`, so that the server's own inputs (`CLOCK_PREFIX`,
#: `BOT_PREFIX`) live where no client can write.
SHOT_ID_CORE = r"[A-Za-z0-9_-]{8,64}"
SHOT_ID_PATTERN = _whole(SHOT_ID_CORE)
#: The input id of the stroke the shot clock plays for the seat to act.
CLOCK_PREFIX = "clock:"
#: The input id of a bot's move.
BOT_PREFIX = "bot:"
#: The id of a played input: a client's shot id or one of the server's own.
INPUT_ID_PATTERN = _whole(rf"(?:{SHOT_ID_CORE}|(?:clock|bot):[0-9]{{8,}})")


def new_table_id() -> str:
    """80 random bits: a private table's id is its invitation and cannot be guessed."""
    return secrets.token_hex(10)


def new_player_id() -> str:
    return f"p_{secrets.token_hex(8)}"


def new_challenge_id() -> str:
    return f"c_{secrets.token_hex(8)}"


def new_replay_id() -> str:
    return secrets.token_hex(12)


#: A shared position's code (rules.compact's position link: base64url), and the query
#: parameter of the practice page that sets it up.
POSITION_CODE_CORE = r"[A-Za-z0-9_-]{1,400}"
POSITION_PARAM = "position"


def practice_url(game: str, code: str) -> str:
    """The practice page that sets up a shared position."""
    return f"/practice/{game}?{POSITION_PARAM}={code}"


def derived_table_id(purpose: str, source_id: str) -> str:
    """The id of the one table made for `purpose` from `source_id` (a match's rematch, an
    accepted challenge): every replica computes the same, and storage refuses a second table
    under it. As hard to guess as the id it comes from."""
    return hashlib.sha256(f"{purpose}:{source_id}".encode()).hexdigest()[:20]


def server_input_id(prefix: str, version: int) -> str:
    """The id of an input the server makes at a table version (never a client's shot id)."""
    return f"{prefix}{version:08d}"


# ----- channels -------------------------------------------------------------------------------
#: The lobby's snapshots.
LOBBY = "public-lobby"
#: Each game's top breaks after a new entry.
LEADERBOARD = "public-leaderboard"
TABLE_CHANNEL_PREFIX = "table-"
PLAYER_CHANNEL_PREFIX = "player-"


def table_channel(table_id: str) -> str:
    """A table's channel: its outcomes, views, presence and quick messages."""
    return f"{TABLE_CHANNEL_PREFIX}{table_id}"


def player_channel(player_id: str) -> str:
    """A player's own channel: its quick-match pairing."""
    return f"{PLAYER_CHANNEL_PREFIX}{player_id}"


class MessageKind(StrEnum):
    """The `kind` of every message published on a channel (server/protocol/models.py), which
    a subscriber switches on."""

    OUTCOME = "outcome"
    TABLE = "table"
    PRESENCE = "presence"
    CHAT = "chat"
    AIM = "aim"
    LOBBY = "lobby"
    PAIRED = "paired"
    CHALLENGE = "challenge"
    LEADERBOARD = "leaderboard"


# ----- timings and limits ---------------------------------------------------------------------
#: Seconds between the heartbeats a seated player's client sends: a player is shown
#: disconnected after `PRESENCE_TIMEOUT` without one, so two may be lost before that happens.
HEARTBEAT_INTERVAL = 3.0
PRESENCE_TIMEOUT = 10.0
#: Seconds a rematch offer stands: a finished table's players send no heartbeats, so an offer
#: its player may have walked away from lapses; accepting it later is an offer of one's own
#: (before, a stale offer seated its absent player at a rated match the other then claimed).
REMATCH_LAPSE = 60.0
#: Seconds between the `GET /api/quick` polls of a client waiting for a quick match: a request
#: lapses `QUICK_LAPSE` seconds after its last poll, so a client that died is never paired.
QUICK_POLL = 5.0
QUICK_LAPSE = 3 * QUICK_POLL
#: Challenges a player may have waiting for an answer at once.
CHALLENGES_PENDING = 5
#: The shot clock of a quick match (s): no seat of a pairing may hold the match forever.
QUICK_SHOT_CLOCK = 60
#: Seconds per shot a table may set (0: no clock).
SHOT_CLOCK_MIN, SHOT_CLOCK_MAX = 10, 300
RACE_TO_MAX = 15
#: Snooker's reds a table may be played with, and three-cushion's points to win (0: the
#: rules' default, `THREE_CUSHION_TARGET`); the pages offer `THREE_CUSHION_TARGETS` (the seed
#: project's races and a short race to 5), the API takes any target up to `TARGET_MAX`.
SNOOKER_REDS = (6, 10, 15)
TARGET_MAX = 100
THREE_CUSHION_TARGET = DEFAULT_TARGET
THREE_CUSHION_TARGETS = (5, 7, 10, 15, 25, 40)
#: The shot clocks the pages offer when a table or challenge is made (s; 0: none).
SHOT_CLOCKS = (0, 30, 60, 120)
#: Seconds the player to act at a match with no shot clock has before the clock plays for them
#: (the timeout input): a player who is there but never acts cannot hold the match, whose
#: opponent could otherwise only resign. Practice and bot tables hold nobody else: none.
TURN_LIMIT = 300
#: Rated matches whose ratings a profile's graph shows (the player's most recent, every game).
PROFILE_HISTORY = 200
#: Pool's table sizes in feet (the games played on them), and the standard one, which the
#: leaderboards rank and every other game is played at.
TABLE_SIZES: tuple[int, ...] = tuple(sorted(POOL_SIZES))
TABLE_SIZE = STANDARD_SIZE
SIZED_GAMES: tuple[str, ...] = tuple(game.value for game in POOL_GAMES)
#: Largest request body accepted (bytes): an intent is a few hundred.
MAX_BODY = 16 * 1024
#: Largest claim body (bytes): a long game's record.
MAX_RECORD_BODY = 1024 * 1024
#: Seconds a request's body may take to arrive, all of it (a client that sends its headers
#: and then dribbles or stops would otherwise hold its request, and a connection, forever).
BODY_SECONDS = 10.0
#: Shots in one answer of `GET /api/replays/{id}/shots` (a page; `?page=` asks for the next):
#: a snooker frame's motion is tens of MB, more than one answer should carry.
REPLAY_SHOTS_PAGE = 200
