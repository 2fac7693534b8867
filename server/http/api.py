"""The game service's HTTP endpoints under `/api/` (docs/protocol.md), declared in one table.

`ROUTES` is the single source for both the router and the OpenAPI description
(server/http/openapi.py): each route names its request model and its answers by status. Bodies are
JSON of at most `MAX_BODY` bytes (claims: `MAX_RECORD_BODY`), parsed into their pydantic model
in strict mode (unknown fields, wrong types such as `"3.0"` or `true` for a number, NaN and
over-deep nesting are refused there); every refusal is `ApiError` JSON.
"""

from __future__ import annotations

import asyncio
import json
import math
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass, field
from typing import TypeVar

from aiohttp import web
from pydantic import BaseModel, ValidationError
from redis.exceptions import RedisError

from physics.scene import unique_keys
from server.game import commands, positions, tables
from server.game.diagrams import SHIPPED, real_shot_list
from server.game.lobby import new_seed
from server.game.profiles import bots, named, profile, rating_view
from server.game.service import NAMES_PER_ADDRESS, SERVICE_KEY, Service, running_service
from server.game.tables import GRACE, TableRecord
from server.protocol import ids
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import BODY_SECONDS, MAX_BODY, MAX_RECORD_BODY, new_table_id
from server.protocol.models import (
    AimMessage,
    AimRequest,
    ApiError,
    BotList,
    BreakEntry,
    Challenge,
    ChallengeCreate,
    ChallengeList,
    ChallengeStatus,
    ChatMessage,
    ClaimRequest,
    ClaimVerdict,
    Intent,
    IntentAccepted,
    IntentDuplicate,
    Leaderboard,
    PlayerCreate,
    PlayerInfo,
    PlayerProfile,
    PlayerRatings,
    PlayerToken,
    PositionShare,
    PresenceMessage,
    QuickMessageRequest,
    QuickRequest,
    QuickStatus,
    RackRequest,
    ReplayShots,
    ReplayView,
    SharedPosition,
    TableCreate,
    TableList,
    TableView,
)
from server.protocol.real_shots import RealShotFit, RealShotFitRequest, RealShotList
from server.relay import JSON, Relay, bearer_token, client_address, media_type, relay_of
from server.storage import StorageError

# Route parameters, from the protocol's formats (server/protocol/ids.py).
TABLE_ID = f"{{table:{ids.TABLE_ID_CORE}}}"
GAME = f"{{game:{'|'.join(ids.GAMES)}}}"
NAME = f"{{name:{ids.NAME_CORE}}}"
PLAYER_ID = f"{{player:{ids.PLAYER_ID_CORE}}}"
REPLAY_ID = f"{{replay:{ids.REPLAY_ID_CORE}}}"
CHALLENGE_ID = f"{{challenge:{ids.CHALLENGE_ID_CORE}}}"
REAL_SHOT_ID = f"{{shot:{ids.REAL_SHOT_ID_CORE}}}"
POSITION_CODE = f"{{code:{ids.POSITION_CODE_CORE}}}"

M = TypeVar("M", bound=BaseModel)
Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


@dataclass(frozen=True)
class Route:
    method: str
    path: str
    handler: Handler
    summary: str
    answers: dict[int, type[BaseModel]]
    body: type[BaseModel] | None = None
    auth: bool = True
    refusals: tuple[ErrorCode, ...] = field(default=())
    max_body: int = MAX_BODY


def service_of(request: web.Request) -> Service:
    return request.app[SERVICE_KEY]


def answer(model: BaseModel, status: int = 200) -> web.Response:
    return web.Response(text=model.model_dump_json(), status=status, content_type=JSON)


def refusal(error: ServiceError) -> web.Response:
    body = ApiError(code=error.code, reason=error.reason, rule=error.rule)
    headers = {"WWW-Authenticate": "Bearer"} if error.code is ErrorCode.UNAUTHORIZED else {}
    return web.Response(
        text=body.model_dump_json(), status=error.status, content_type=JSON, headers=headers
    )


async def parse(request: web.Request, model: type[M], limit: int = MAX_BODY) -> M:
    """The request's body as `model`; ServiceError for anything else."""
    return parse_body(await read_body(request, limit), model)


async def read_body(request: web.Request, limit: int = MAX_BODY) -> bytes:
    """The request's JSON body, at most `limit` bytes, all of it within BODY_SECONDS;
    ServiceError for anything else."""
    if media_type(request.content_type) != JSON:
        raise ServiceError(ErrorCode.UNSUPPORTED_MEDIA_TYPE, "send application/json")
    data = bytearray()
    try:
        async with asyncio.timeout(BODY_SECONDS):
            while chunk := await request.content.read(limit + 1 - len(data)):
                data += chunk
                if len(data) > limit:
                    raise ServiceError(
                        ErrorCode.BODY_TOO_LARGE, f"bodies here are at most {limit} bytes"
                    )
    except TimeoutError:
        raise ServiceError(
            ErrorCode.REQUEST_TIMEOUT, f"the body did not arrive within {BODY_SECONDS:g} s"
        ) from None
    return bytes(data)


def parse_body(data: bytes, model: type[M]) -> M:
    """A JSON body as `model` (strict: module docstring); ServiceError for anything else."""
    try:
        return model.model_validate_json(canonical_json(data), strict=True)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(part) for part in first["loc"]) or "body"
        # A model's own check (a miscue: |(a, b)| > 0.5) refuses a well-formed body: the
        # rules' refusal, not a malformed request.
        code = ErrorCode.ILLEGAL_INPUT if first["type"] == "value_error" else ErrorCode.BAD_REQUEST
        raise ServiceError(code, f"{where}: {first['msg']}") from None


def _number(text: str) -> int | float:
    """A JSON number: finite, and an integer when it has no fraction (8.0 is 8 in JSON Schema;
    strict validation then takes it for an int field and, as 8, for a float field)."""
    value = float(text)
    if not math.isfinite(value):
        raise ServiceError(ErrorCode.BAD_REQUEST, f"number {text[:20]} is out of range")
    return int(value) if value.is_integer() and abs(value) < 2**63 else value


def _no_constant(name: str) -> None:
    raise ServiceError(ErrorCode.BAD_REQUEST, f"{name} is not a JSON number")


def canonical_json(data: bytes) -> str:
    """The body re-encoded with integral numbers as integers; BAD_REQUEST for what is not
    JSON (NaN, infinities, invalid text, a key twice in an object, nesting too deep for a
    parser)."""
    try:
        value = json.loads(
            data, parse_float=_number, parse_constant=_no_constant, object_pairs_hook=unique_keys
        )
    except (ValueError, RecursionError) as error:
        reason = "too deeply nested" if isinstance(error, RecursionError) else str(error)
        raise ServiceError(ErrorCode.BAD_REQUEST, f"body is not JSON: {reason}") from None
    return json.dumps(value, separators=(",", ":"))


async def player_of(request: web.Request) -> PlayerInfo:
    """The player whose token is in the Authorization header (never in the URL: docs)."""
    token = bearer_token(request, query=False)
    if token is None:
        raise ServiceError(ErrorCode.UNAUTHORIZED, "send the token as Authorization: Bearer")
    return await service_of(request).identity.authenticate(token)


async def table_of(request: web.Request) -> TableRecord:
    record = await service_of(request).storage.get_table(request.match_info["table"])
    if record is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such table")
    return record


async def full_view(service: Service, record: TableRecord) -> TableView:
    seen = await service.matches.context.seen(record.id)
    return tables.view(record, seen, await service.lobby.spectators(record))


# ----- identity -------------------------------------------------------------------------------
async def register(request: web.Request) -> web.Response:
    create = await parse(request, PlayerCreate)
    service = service_of(request)
    relay = relay_of(request)
    service.throttle("register", client_address(request, relay.trusted_proxies))
    token = await service.identity.register(create.name)
    service.lobby.changed()  # one more player online
    return answer(token, 201)


async def me(request: web.Request) -> web.Response:
    return answer(await player_of(request))


async def player_ratings(request: web.Request) -> web.Response:
    storage = service_of(request).storage
    player = await storage.get_player(request.match_info["player"])
    if player is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such player")
    views = {game: rating_view(r) for game, r in (await storage.ratings(player.id)).items()}
    return answer(PlayerRatings(player=player, ratings=views))


async def list_bots(request: web.Request) -> web.Response:
    return answer(await bots(service_of(request).storage))


async def player_named(request: web.Request) -> web.Response:
    return answer(await named(service_of(request).storage, request.match_info["name"]))


async def player_profile(request: web.Request) -> web.Response:
    return answer(await profile(service_of(request).storage, request.match_info["player"]))


# ----- tables ---------------------------------------------------------------------------------
async def create_table(request: web.Request) -> web.Response:
    player = await player_of(request)
    create = await parse(request, TableCreate)
    service = service_of(request)
    service.throttle("create", player.id)
    create = await service.lobby.listing(player, create)
    record = tables.new_table(new_table_id(), create, player, new_seed())
    await service.storage.create_table(record)
    service.lobby.changed()
    return answer(await full_view(service, record), 201)


async def list_tables(request: web.Request) -> web.Response:
    return answer(await service_of(request).lobby.tables())


async def get_table(request: web.Request) -> web.Response:
    """A read: it starts no work (no bot search, no replay of an abandoned input)."""
    return answer(await full_view(service_of(request), await table_of(request)))


async def _ask(request: web.Request, command: commands.ClientCommand) -> object:
    """Hand `command` to the table's actor and return its answer (after a cheap look that
    the table exists, so that unknown ids start no actor)."""
    service = service_of(request)
    await table_of(request)
    return await service.matches.owner(request.match_info["table"]).ask(command)


async def _seat_command(
    request: web.Request,
    make: Callable[[PlayerInfo], commands.ClientCommand],
    limit: str | None = None,
) -> web.Response:
    """Join, leave, resign, claim, rematch and retake: the command (its player's `limit`
    taken first, if it has one), then the table as it now is."""
    player = await player_of(request)
    if limit is not None:
        service_of(request).throttle(limit, player.id)
    after = await _ask(request, make(player))
    assert isinstance(after, TableRecord)
    return answer(await full_view(service_of(request), after))


async def join(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Join)


async def leave(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Leave)


async def resign(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Resign)


async def claim(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Claim)


async def rematch(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Rematch)


async def rack(request: web.Request) -> web.Response:
    """Practice: the next rack, from a set-up position or the game's own rack."""
    player = await player_of(request)
    body = await parse(request, RackRequest)
    service_of(request).throttle("practice", player.id)
    after = await _ask(request, commands.Rerack(player, body.position))
    assert isinstance(after, TableRecord)
    return answer(await full_view(service_of(request), after))


async def retake(request: web.Request) -> web.Response:
    return await _seat_command(request, commands.Retake, limit="practice")


# ----- shared positions -------------------------------------------------------------------------
async def share_position(request: web.Request) -> web.Response:
    return answer(positions.share(await parse(request, PositionShare)))


async def open_position(request: web.Request) -> web.Response:
    return answer(positions.open_link(request.match_info["code"]))


async def intent(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, Intent)
    result = await _ask(request, commands.Play(player, body))
    assert isinstance(result, IntentAccepted | IntentDuplicate)
    return answer(result, 202 if isinstance(result, IntentAccepted) else 200)


async def heartbeat(request: web.Request) -> web.Response:
    player = await player_of(request)
    service = service_of(request)
    service.throttle("heartbeat", player.id)
    message = await _ask(request, commands.Heartbeat(player))
    assert isinstance(message, PresenceMessage)
    await service.identity.seen(player)
    return answer(message)


async def quick_message(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, QuickMessageRequest)
    service = service_of(request)
    service.throttle("chat", f"{request.match_info['table']}:{player.id}")
    message = await _ask(request, commands.QuickMessage(player, body.message))
    assert isinstance(message, ChatMessage)
    return answer(message, 201)


async def aim(request: web.Request) -> web.Response:
    """Pass on the aim of the player to act to the table's readers (opponent, spectators)."""
    player = await player_of(request)
    body = await parse(request, AimRequest)
    service = service_of(request)
    service.throttle("aim", f"{request.match_info['table']}:{player.id}")
    message = await _ask(request, commands.Aim(player, body))
    assert isinstance(message, AimMessage)
    return answer(message, 201)


# ----- replays and the leaderboard -------------------------------------------------------------
async def get_replay(request: web.Request) -> web.Response:
    replay = await service_of(request).storage.get_replay(request.match_info["replay"])
    if replay is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such replay")
    return answer(replay)


async def replay_shots(request: web.Request) -> web.Response:
    """A page of a replay's shots (`?page=`, from 0), computing charged to the asker's address."""
    text = request.query.get("page", "0")
    if not (text.isdigit() and text.isascii() and len(text) <= 6):
        raise ServiceError(ErrorCode.BAD_REQUEST, "page is a number from 0")
    asker = client_address(request, relay_of(request).trusted_proxies)
    shots = await service_of(request).replay_shots.shots(
        request.match_info["replay"], int(text), asker
    )
    return web.Response(body=shots, content_type=JSON)


async def leaderboard(request: web.Request) -> web.Response:
    return answer(await service_of(request).breaks.top(request.match_info["game"]))


async def best_break(request: web.Request) -> web.Response:
    game, name = request.match_info["game"], request.match_info["name"]
    entry = await service_of(request).storage.best_break(game, name)
    if entry is None:
        raise ServiceError(ErrorCode.NOT_FOUND, f"no {game} break under {name!r}")
    return answer(entry)


async def claim_break(request: web.Request) -> web.Response:
    """Refused in order of cost: the token, the claim rate, the holder's worker time and the
    event loop's share for claims, a body refused before; then the body is parsed and
    `Breaks.claim` goes on."""
    player = await player_of(request)
    service = service_of(request)
    service.throttle("claim", player.id)
    address = client_address(request, relay_of(request).trusted_proxies)
    breaks = service.breaks
    breaks.may_parse(player.id, address)
    data = await read_body(request, MAX_RECORD_BODY)
    breaks.refused_before(data)
    # Again, now that the body is in: claims read at once all passed the first check before
    # any of their parses was charged (before, 100 of them from one address took 12 s).
    breaks.may_parse(player.id, address)
    began = breaks.budget.clock()
    try:  # parsing a long record takes the event loop tens of ms: the holder's time too
        claim = parse_body(data, ClaimRequest)
    finally:
        breaks.parsed(breaks.budget.clock() - began, player.id, address)
    return answer(await service.breaks.claim(player, address, claim, data), 201)


# ----- recorded real shots (the diagrams page) --------------------------------------------------
async def real_shots(_: web.Request) -> web.Response:
    return answer(real_shot_list())


async def real_shot(request: web.Request) -> web.Response:
    """A recorded shot with its shipped fit drawn (computed once, then kept)."""
    asker = client_address(request, relay_of(request).trusted_proxies)
    data = await service_of(request).diagrams.real_shot(
        int(request.match_info["shot"]), SHIPPED, False, asker
    )
    return web.Response(body=data, content_type=JSON)


async def refit_real_shot(request: web.Request) -> web.Response:
    """A refit within its bound; the asker's worker time is checked before the body is read."""
    asker = client_address(request, relay_of(request).trusted_proxies)
    work = service_of(request).diagrams
    work.budget.check(asker)
    body = await parse(request, RealShotFitRequest)
    data = await work.real_shot(int(request.match_info["shot"]), body, True, asker)
    return web.Response(body=data, content_type=JSON)


# ----- quick match ----------------------------------------------------------------------------
async def quick(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, QuickRequest)
    service = service_of(request)
    service.throttle("quick", player.id)
    return answer(await service.lobby.quick(player, body))


async def quick_status(request: web.Request) -> web.Response:
    """A waiting page's poll: its player is online (`Identity.seen`), as at a table."""
    player = await player_of(request)
    service = service_of(request)
    await service.identity.seen(player)
    return answer(await service.lobby.quick_status(player))


async def quick_cancel(request: web.Request) -> web.Response:
    player = await player_of(request)
    cancelled = await service_of(request).storage.cancel_quick(player.id)
    return answer(QuickStatus(status="cancelled" if cancelled else "idle"))


# ----- challenges -----------------------------------------------------------------------------
async def challenge(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, ChallengeCreate)
    service = service_of(request)
    service.throttle("challenge", player.id)
    return answer(await service.challenges.create(player, body), 201)


async def challenges(request: web.Request) -> web.Response:
    """The lobby page's poll: its player is online (`Identity.seen`), as at a table; before,
    a player on the lobby page lost their name after `ONLINE` (5 minutes) to whoever took it."""
    player = await player_of(request)
    service = service_of(request)
    await service.identity.seen(player)
    return answer(await service.challenges.pending(player))


def _answer_challenge(to: ChallengeStatus) -> Handler:
    async def handler(request: web.Request) -> web.Response:
        player = await player_of(request)
        settled = await service_of(request).challenges.answer(
            player, request.match_info["challenge"], to
        )
        return answer(settled)

    return handler


_TABLE_REFUSALS = (ErrorCode.NOT_FOUND, ErrorCode.FORBIDDEN, ErrorCode.WRONG_PHASE)
_T = f"/api/tables/{TABLE_ID}"
ROUTES: tuple[Route, ...] = (
    Route("POST", "/api/players", register, "A guest identity and its token", {201: PlayerToken},
          PlayerCreate, auth=False, refusals=(ErrorCode.NAME_TAKEN, ErrorCode.RATE_LIMITED)),
    Route("GET", "/api/me", me, "The player a token names", {200: PlayerInfo}),
    Route("GET", f"/api/players/named/{NAME}", player_named,
          "The player a display name stands for: its holder online, else its last holder",
          {200: PlayerInfo}, auth=False, refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", f"/api/players/{PLAYER_ID}/ratings", player_ratings,
          "A player's rating in each game", {200: PlayerRatings}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", f"/api/players/{PLAYER_ID}/profile", player_profile,
          "A player's ratings and their history, recent matches, best breaks, last seen",
          {200: PlayerProfile}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", "/api/bots", list_bots, "The bots' levels, names and ratings", {200: BotList},
          auth=False),
    Route("POST", "/api/tables", create_table, "Create a table", {201: TableView}, TableCreate,
          refusals=(ErrorCode.RATE_LIMITED, ErrorCode.TOO_MANY_TABLES)),
    Route("GET", "/api/tables", list_tables, "Open and live public tables", {200: TableList},
          auth=False),
    Route("GET", _T, get_table, "A table's full state (resync)", {200: TableView}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("POST", f"{_T}/join", join, "Take the free seat", {200: TableView},
          refusals=(ErrorCode.NOT_FOUND, ErrorCode.TABLE_FULL, ErrorCode.ALREADY_SEATED)),
    Route("POST", f"{_T}/leave", leave, "Cancel an open table", {200: TableView},
          refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/intents", intent, "Send a shot or a choice",
          {202: IntentAccepted, 200: IntentDuplicate}, Intent,
          refusals=(*_TABLE_REFUSALS, ErrorCode.NOT_YOUR_TURN, ErrorCode.STALE_VERSION,
                    ErrorCode.ILLEGAL_INPUT, ErrorCode.DUPLICATE, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/resign", resign, "Resign the match", {200: TableView},
          refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/claim", claim, "Claim the win from an absent opponent",
          {200: TableView}, refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/rematch", rematch, "Offer or accept a rematch", {200: TableView},
          refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/rack", rack, "Practice: re-rack, or set up a position",
          {200: TableView}, RackRequest,
          refusals=(*_TABLE_REFUSALS, ErrorCode.BAD_POSITION, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/retake", retake, "Practice: take the last shot again",
          {200: TableView}, refusals=(*_TABLE_REFUSALS, ErrorCode.RATE_LIMITED)),
    Route("POST", "/api/positions", share_position, "A set-up position's share link",
          {200: SharedPosition}, PositionShare, auth=False,
          refusals=(ErrorCode.BAD_POSITION, ErrorCode.BAD_REQUEST)),
    Route("GET", f"/api/positions/{POSITION_CODE}", open_position,
          "What a shared position sets up", {200: SharedPosition}, auth=False,
          refusals=(ErrorCode.BAD_POSITION, ErrorCode.BAD_REQUEST, ErrorCode.NOT_FOUND)),
    Route("POST", f"{_T}/heartbeat", heartbeat, "I am still here", {200: PresenceMessage},
          refusals=(*_TABLE_REFUSALS, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/messages", quick_message, "Send a quick message", {201: ChatMessage},
          QuickMessageRequest, refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/aim", aim, "Show my aim to the table", {201: AimMessage}, AimRequest,
          refusals=(*_TABLE_REFUSALS, ErrorCode.RATE_LIMITED)),
    Route("GET", f"/api/replays/{REPLAY_ID}", get_replay, "A rack's replay",
          {200: ReplayView}, auth=False, refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", f"/api/replays/{REPLAY_ID}/shots", replay_shots,
          "A page of a replay's inputs with their outcomes and motion (?page=)",
          {200: ReplayShots}, auth=False,
          refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED, ErrorCode.ILLEGAL_INPUT,
                    ErrorCode.BAD_REQUEST)),
    Route("GET", f"/api/leaderboard/{GAME}", leaderboard, "A game's highest breaks",
          {200: Leaderboard}, auth=False, refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", f"/api/leaderboard/{GAME}/players/{NAME}", best_break,
          "A name's best break in a game", {200: BreakEntry}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("POST", "/api/leaderboard/claims", claim_break, "Claim a break from a game record",
          {201: ClaimVerdict}, ClaimRequest, max_body=MAX_RECORD_BODY,
          refusals=(ErrorCode.ILLEGAL_INPUT, ErrorCode.CLAIM_MISMATCH, ErrorCode.DUPLICATE,
                    ErrorCode.RATE_LIMITED, ErrorCode.FORBIDDEN)),
    Route("GET", "/api/real-shots", real_shots,
          "The recorded real-table shots and their shipped fits' figures", {200: RealShotList},
          auth=False),
    Route("GET", f"/api/real-shots/{REAL_SHOT_ID}", real_shot,
          "A recorded shot's tracks with its shipped fit simulated", {200: RealShotFit},
          auth=False, refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED)),
    Route("POST", f"/api/real-shots/{REAL_SHOT_ID}/fit", refit_real_shot,
          "Refit a recorded shot's strike, within a bound of simulations and CPU",
          {200: RealShotFit}, RealShotFitRequest, auth=False,
          refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED)),
    Route("POST", "/api/quick", quick, "Ask for a quick match", {200: QuickStatus}, QuickRequest,
          refusals=(ErrorCode.RATE_LIMITED,)),
    Route("GET", "/api/quick", quick_status, "Where my quick match stands", {200: QuickStatus}),
    Route("DELETE", "/api/quick", quick_cancel, "Stop waiting", {200: QuickStatus}),
    Route("POST", "/api/challenges", challenge, "Challenge a player", {201: Challenge},
          ChallengeCreate, refusals=(ErrorCode.NOT_FOUND, ErrorCode.ILLEGAL_INPUT,
                                     ErrorCode.RATE_LIMITED)),
    Route("GET", "/api/challenges", challenges, "My pending challenges (and I am here)",
          {200: ChallengeList}),
    *(
        Route("POST", f"/api/challenges/{CHALLENGE_ID}/{verb}", _answer_challenge(to),
              f"{verb.capitalize()} a challenge", {200: Challenge},
              refusals=(ErrorCode.NOT_FOUND, ErrorCode.FORBIDDEN, ErrorCode.WRONG_PHASE))
        for verb, to in (("accept", ChallengeStatus.ACCEPTED),
                         ("decline", ChallengeStatus.DECLINED),
                         ("cancel", ChallengeStatus.CANCELLED))
    ),
)  # fmt: skip


def refusing(handler: Handler) -> Handler:
    """`handler` with its refusals answered as ApiError JSON. Each /api/ route is wrapped so,
    rather than the application having a middleware: aiohttp runs an application's middleware
    chain for every request it takes once any is installed, the relay's publishes and
    subscribes included, which then pass through the game API's error handling (5% of the
    relay's CPU per publish on a shared machine; within the noise on a quiet one)."""

    async def answered(request: web.Request) -> web.StreamResponse:
        try:
            return await handler(request)
        except ServiceError as error:
            return refusal(error)
        except (StorageError, RedisError, OSError) as error:
            return refusal(ServiceError(ErrorCode.UNAVAILABLE, f"storage unavailable: {error}"))

    return answered


async def unrouted(request: web.Request) -> web.Response:
    """An /api/ request no route takes (the last route under /api/): 405 with the methods
    its path has, or 404, as ApiError JSON."""
    allowed: set[str] = set()
    for resource in request.app.router.resources():
        if resource is not request.match_info.route.resource:
            allowed |= (await resource.resolve(request))[1]
    if not allowed:
        return refusal(ServiceError(ErrorCode.NOT_FOUND, f"no such resource: {request.path}"))
    body = ApiError(code=ErrorCode.BAD_REQUEST, reason="method not allowed")
    return web.Response(
        text=body.model_dump_json(),
        status=405,
        content_type=JSON,
        headers={"Allow": ",".join(sorted(allowed))},
    )


async def _openapi(request: web.Request) -> web.Response:
    from server.http.openapi import openapi_document

    return web.json_response(openapi_document())


def mount_api(
    app: web.Application,
    relay: Relay,
    *,
    database: str | None,
    redis_url: str | None,
    workers: int | None,
    grace: float = GRACE,
    names_per_address: int = NAMES_PER_ADDRESS,
) -> None:
    """Add the `/api/` routes, their error handling and the service's lifetime to `app`
    (after every other route: the last one takes what no route under /api/ took)."""
    for route in ROUTES:
        if route.method == "GET":  # and HEAD, as HTTP asks of every GET
            app.router.add_get(route.path, refusing(route.handler))
        else:
            app.router.add_route(route.method, route.path, refusing(route.handler))
    app.router.add_get("/api/openapi.json", _openapi)
    app.router.add_route("*", r"/api/{path:[\s\S]*}", unrouted)

    async def lifetime(app: web.Application) -> AsyncIterator[None]:
        async with running_service(
            relay, database, redis_url, workers, grace, names_per_address
        ) as service:
            app[SERVICE_KEY] = service
            yield

    app.cleanup_ctx.append(lifetime)
