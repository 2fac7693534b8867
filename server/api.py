"""The game service's HTTP endpoints under `/api/` (docs/protocol.md), declared in one table.

`ROUTES` is the single source for both the router and the OpenAPI description
(server/openapi.py): each route names its request model and its answers by status. Bodies are
JSON of at most `MAX_BODY` bytes (claims: `MAX_RECORD_BODY`), parsed into their pydantic model
in strict mode (unknown fields, wrong types such as `"3.0"` or `true` for a number, NaN and
over-deep nesting are refused there); every refusal is `ApiError` JSON.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass, field
from typing import TypeVar

from aiohttp import web
from pydantic import BaseModel, ValidationError
from redis.exceptions import RedisError

from server import tables
from server.api_models import (
    AimMessage,
    AimRequest,
    ApiError,
    BreakEntry,
    ChatMessage,
    ClaimRequest,
    ClaimVerdict,
    Intent,
    IntentAccepted,
    IntentDuplicate,
    Leaderboard,
    Mode,
    PlayerCreate,
    PlayerInfo,
    PlayerRatings,
    PlayerToken,
    PresenceMessage,
    QuickMessageRequest,
    QuickRequest,
    QuickStatus,
    RatingView,
    ReplayShots,
    ReplayView,
    Status,
    TableCreate,
    TableList,
    TableView,
)
from server.errors import ErrorCode, ServiceError
from server.lobby import new_seed, new_table_id
from server.relay.addresses import client_address
from server.relay.http import bearer_token, relay_of
from server.relay.payloads import JSON, media_type
from server.relay.relay import Relay
from server.service import SERVICE_KEY, Service, running_service
from server.storage import StorageError
from server.tables import GRACE, TableRecord

#: Largest request body accepted (bytes): an intent is a few hundred.
MAX_BODY = 16 * 1024
#: Largest claim body (bytes): a long game's record (rules.record.MAX_INPUTS inputs).
MAX_RECORD_BODY = 1024 * 1024
TABLE_ID = r"{table:[0-9a-f]{20}}"
GAME = r"{game:nineball|eightball|snooker|three_cushion}"
NAME = r"{name:[A-Za-z0-9_. \-]{1,24}}"

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
    if media_type(request.content_type) != JSON:
        raise ServiceError(ErrorCode.UNSUPPORTED_MEDIA_TYPE, "send application/json")
    data = bytearray()
    while chunk := await request.content.read(limit + 1 - len(data)):
        data += chunk
        if len(data) > limit:
            raise ServiceError(ErrorCode.BODY_TOO_LARGE, f"bodies here are at most {limit} bytes")
    try:
        return model.model_validate_json(canonical_json(bytes(data)), strict=True)
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
    JSON (NaN, infinities, invalid text, nesting too deep for a parser)."""
    try:
        value = json.loads(data, parse_float=_number, parse_constant=_no_constant)
    except (ValueError, RecursionError) as error:
        reason = "too deeply nested" if isinstance(error, RecursionError) else str(error)
        raise ServiceError(ErrorCode.BAD_REQUEST, f"body is not JSON: {reason}") from None
    return json.dumps(value, separators=(",", ":"))


async def player_of(request: web.Request) -> PlayerInfo:
    return await service_of(request).identity.authenticate(bearer_token(request))


async def table_of(request: web.Request) -> TableRecord:
    record = await service_of(request).storage.get_table(request.match_info["table"])
    if record is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such table")
    return record


async def full_view(service: Service, record: TableRecord) -> TableView:
    seen = await service.storage.heartbeats(record.id)
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
    views = {
        game: RatingView(**rating.model_dump(), provisional=rating.provisional)
        for game, rating in (await storage.ratings(player.id)).items()
    }
    return answer(PlayerRatings(player=player, ratings=views))


# ----- tables ---------------------------------------------------------------------------------
async def create_table(request: web.Request) -> web.Response:
    player = await player_of(request)
    create = await parse(request, TableCreate)
    service = service_of(request)
    service.throttle("create", player.id)
    record = tables.new_table(new_table_id(), create, player, new_seed())
    await service.storage.create_table(record)
    service.lobby.changed()
    return answer(await full_view(service, record), 201)


async def list_tables(request: web.Request) -> web.Response:
    return answer(await service_of(request).lobby.tables())


async def get_table(request: web.Request) -> web.Response:
    record = await table_of(request)
    service = service_of(request)
    service.matches.owner(record.id).poke()
    return answer(await full_view(service, record))


async def _change(
    request: web.Request, change: Callable[[TableRecord], TableRecord]
) -> web.Response:
    service = service_of(request)
    await table_of(request)
    after = await service.matches.owner(request.match_info["table"]).change(change)
    return answer(await full_view(service, after))


def _seated(record: TableRecord, player: PlayerInfo) -> int:
    seat = tables.seat_of(record, player.id)
    if seat is None:
        raise ServiceError(ErrorCode.FORBIDDEN, "you do not sit at this table")
    return seat


async def join(request: web.Request) -> web.Response:
    player = await player_of(request)
    return await _change(request, lambda record: tables.join(record, player))


async def leave(request: web.Request) -> web.Response:
    player = await player_of(request)

    def cancel(record: TableRecord) -> TableRecord:
        _seated(record, player)
        if record.status is not Status.OPEN:
            raise ServiceError(ErrorCode.WRONG_PHASE, "the table has started: resign instead")
        return tables.bump(record, status=Status.CANCELLED)

    return await _change(request, cancel)


async def resign(request: web.Request) -> web.Response:
    player = await player_of(request)

    def give_up(record: TableRecord) -> TableRecord:
        seat = _seated(record, player)
        if record.status is not Status.PLAYING:
            raise ServiceError(ErrorCode.WRONG_PHASE, f"the table is {record.status.value}")
        winner = None if record.mode is Mode.PRACTICE else 1 - seat
        return tables.bump(record, status=Status.OVER, winner=winner)

    return await _change(request, give_up)


async def claim(request: web.Request) -> web.Response:
    player = await player_of(request)
    service = service_of(request)
    seen = await service.storage.heartbeats(request.match_info["table"])

    def win(record: TableRecord) -> TableRecord:
        seat = _seated(record, player)
        if record.status is not Status.PLAYING or record.mode is not Mode.MATCH:
            raise ServiceError(ErrorCode.WRONG_PHASE, "there is no match to claim")
        until = tables.grace_until(record, seen, time.time(), service.grace)[1 - seat]
        if until is None or time.time() < until:
            raise ServiceError(ErrorCode.WRONG_PHASE, "your opponent is here or within grace")
        return tables.bump(record, status=Status.OVER, winner=seat)

    return await _change(request, win)


async def rematch(request: web.Request) -> web.Response:
    player = await player_of(request)
    service = service_of(request)
    record = await table_of(request)
    seat = _seated(record, player)
    if record.status is not Status.OVER or record.mode is not Mode.MATCH:
        raise ServiceError(ErrorCode.WRONG_PHASE, "a rematch follows a finished match")
    new_id = None
    if record.rematch[1 - seat] and record.rematch_table is None:
        # The seats swap, so the break alternates: seat 0 breaks a table's first rack.
        create = TableCreate(game=record.game, **record.options.model_dump())
        first, second = record.seats[1], record.seats[0]
        fresh = tables.join(tables.new_table(new_table_id(), create, first, new_seed()), second)
        await service.storage.create_table(fresh)
        service.lobby.changed()
        new_id = fresh.id

    def offer(current: TableRecord) -> TableRecord:
        offers = list(current.rematch)
        offers[seat] = True
        update: dict = {"rematch": (offers[0], offers[1])}
        if new_id is not None and current.rematch_table is None:
            update["rematch_table"] = new_id
        return tables.bump(current, **update)

    return await _change(request, offer)


async def intent(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, Intent)
    record = await table_of(request)
    result = await service_of(request).matches.owner(record.id).intent(player, body)
    return answer(result, 202 if isinstance(result, IntentAccepted) else 200)


async def heartbeat(request: web.Request) -> web.Response:
    player = await player_of(request)
    service = service_of(request)
    service.throttle("heartbeat", player.id)
    record = await table_of(request)
    seat = _seated(record, player)
    now = time.time()
    await service.storage.heartbeat(record.id, seat, now)
    await service.identity.seen(player)
    service.matches.owner(record.id).poke()
    seen = await service.storage.heartbeats(record.id)
    message = PresenceMessage(
        version=record.version,
        presence=tables.presence(record, seen, now),
        grace_until=tables.grace_until(record, seen, now, service.grace),
    )
    last = service.presence.get(record.id)
    if last is None or last.presence != message.presence:
        service.presence[record.id] = message
        await service.publisher.publish(record.channel, message)
    return answer(message)


async def quick_message(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, QuickMessageRequest)
    service = service_of(request)
    record = await table_of(request)
    service.throttle("chat", f"{record.id}:{player.id}")
    message = ChatMessage(
        version=record.version,
        from_name=player.name,
        seat=tables.seat_of(record, player.id),
        message=body.message,
    )
    await service.publisher.publish(record.channel, message)
    return answer(message, 201)


async def aim(request: web.Request) -> web.Response:
    """Pass on the aim of the player to act to the table's readers (opponent, spectators)."""
    player = await player_of(request)
    body = await parse(request, AimRequest)
    service = service_of(request)
    record = await table_of(request)
    seat = tables.seat_of(record, player.id)
    if seat is None:
        raise ServiceError(ErrorCode.FORBIDDEN, "you do not sit at this table")
    if tables.acting_seat(record) != seat:
        raise ServiceError(ErrorCode.WRONG_PHASE, "only the player to act has an aim to show")
    service.throttle("aim", f"{record.id}:{player.id}")
    message = AimMessage(version=record.version, seat=seat, **body.model_dump())
    await service.publisher.publish(record.channel, message)
    return answer(message, 201)


# ----- replays and the leaderboard -------------------------------------------------------------
async def get_replay(request: web.Request) -> web.Response:
    replay = await service_of(request).storage.get_replay(request.match_info["replay"])
    if replay is None:
        raise ServiceError(ErrorCode.NOT_FOUND, "no such replay")
    return answer(replay)


async def replay_shots(request: web.Request) -> web.Response:
    shots = await service_of(request).replay_shots.shots(request.match_info["replay"])
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
    claim = await parse(request, ClaimRequest, MAX_RECORD_BODY)
    return answer(await service_of(request).breaks.claim(claim), 201)


# ----- quick match ----------------------------------------------------------------------------
async def quick(request: web.Request) -> web.Response:
    player = await player_of(request)
    body = await parse(request, QuickRequest)
    service = service_of(request)
    service.throttle("quick", player.id)
    return answer(await service.lobby.quick(player, TableCreate(game=body.game)))


async def quick_status(request: web.Request) -> web.Response:
    player = await player_of(request)
    return answer(await service_of(request).lobby.quick_status(player))


async def quick_cancel(request: web.Request) -> web.Response:
    player = await player_of(request)
    cancelled = await service_of(request).storage.cancel_quick(player.id)
    return answer(QuickStatus(status="cancelled" if cancelled else "idle"))


_TABLE_REFUSALS = (ErrorCode.NOT_FOUND, ErrorCode.FORBIDDEN, ErrorCode.WRONG_PHASE)
_T = f"/api/tables/{TABLE_ID}"
ROUTES: tuple[Route, ...] = (
    Route("POST", "/api/players", register, "A guest identity and its token", {201: PlayerToken},
          PlayerCreate, auth=False, refusals=(ErrorCode.NAME_TAKEN, ErrorCode.RATE_LIMITED)),
    Route("GET", "/api/me", me, "The player a token names", {200: PlayerInfo}),
    Route("GET", "/api/players/{player:p_[0-9a-f]{16}}/ratings", player_ratings,
          "A player's rating in each game", {200: PlayerRatings}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("POST", "/api/tables", create_table, "Create a table", {201: TableView}, TableCreate,
          refusals=(ErrorCode.RATE_LIMITED,)),
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
                    ErrorCode.ILLEGAL_INPUT)),
    Route("POST", f"{_T}/resign", resign, "Resign the match", {200: TableView},
          refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/claim", claim, "Claim the win from an absent opponent",
          {200: TableView}, refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/rematch", rematch, "Offer or accept a rematch", {200: TableView},
          refusals=_TABLE_REFUSALS),
    Route("POST", f"{_T}/heartbeat", heartbeat, "I am still here", {200: PresenceMessage},
          refusals=(*_TABLE_REFUSALS, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/messages", quick_message, "Send a quick message", {201: ChatMessage},
          QuickMessageRequest, refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED)),
    Route("POST", f"{_T}/aim", aim, "Show my aim to the table", {201: AimMessage}, AimRequest,
          refusals=(*_TABLE_REFUSALS, ErrorCode.RATE_LIMITED)),
    Route("GET", "/api/replays/{replay:[0-9a-f]{24}}", get_replay, "A rack's replay",
          {200: ReplayView}, auth=False, refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", "/api/replays/{replay:[0-9a-f]{24}}/shots", replay_shots,
          "Every input of a replay with its outcome and motion", {200: ReplayShots}, auth=False,
          refusals=(ErrorCode.NOT_FOUND, ErrorCode.RATE_LIMITED, ErrorCode.ILLEGAL_INPUT)),
    Route("GET", f"/api/leaderboard/{GAME}", leaderboard, "A game's highest breaks",
          {200: Leaderboard}, auth=False, refusals=(ErrorCode.NOT_FOUND,)),
    Route("GET", f"/api/leaderboard/{GAME}/players/{NAME}", best_break,
          "A name's best break in a game", {200: BreakEntry}, auth=False,
          refusals=(ErrorCode.NOT_FOUND,)),
    Route("POST", "/api/leaderboard/claims", claim_break, "Claim a break from a game record",
          {201: ClaimVerdict}, ClaimRequest, auth=False, max_body=MAX_RECORD_BODY,
          refusals=(ErrorCode.ILLEGAL_INPUT, ErrorCode.CLAIM_MISMATCH, ErrorCode.DUPLICATE,
                    ErrorCode.RATE_LIMITED)),
    Route("POST", "/api/quick", quick, "Ask for a quick match", {200: QuickStatus}, QuickRequest,
          refusals=(ErrorCode.RATE_LIMITED,)),
    Route("GET", "/api/quick", quick_status, "Where my quick match stands", {200: QuickStatus}),
    Route("DELETE", "/api/quick", quick_cancel, "Stop waiting", {200: QuickStatus}),
)  # fmt: skip


@web.middleware
async def api_errors(request: web.Request, handler: Handler) -> web.StreamResponse:
    """Every refusal under /api/ as ApiError JSON (unknown routes and methods included)."""
    if not request.path.startswith("/api/"):
        return await handler(request)
    try:
        return await handler(request)
    except ServiceError as error:
        return refusal(error)
    except (StorageError, RedisError, OSError) as error:
        return refusal(ServiceError(ErrorCode.UNAVAILABLE, f"storage unavailable: {error}"))
    except web.HTTPNotFound:
        return refusal(ServiceError(ErrorCode.NOT_FOUND, f"no such resource: {request.path}"))
    except web.HTTPMethodNotAllowed as error:
        return web.Response(
            text=ApiError(
                code=ErrorCode.BAD_REQUEST, reason="method not allowed"
            ).model_dump_json(),
            status=405,
            content_type=JSON,
            headers={"Allow": ",".join(sorted(error.allowed_methods))},
        )


async def _openapi(request: web.Request) -> web.Response:
    from server.openapi import openapi_document

    return web.json_response(openapi_document())


def mount_api(
    app: web.Application,
    relay: Relay,
    *,
    database: str | None,
    redis_url: str | None,
    workers: int | None,
    grace: float = GRACE,
) -> None:
    """Add the `/api/` routes, their error handling and the service's lifetime to `app`."""
    app.middlewares.append(api_errors)
    for route in ROUTES:
        app.router.add_route(route.method, route.path, route.handler)
    app.router.add_get("/api/openapi.json", _openapi)

    async def lifetime(app: web.Application) -> AsyncIterator[None]:
        async with running_service(relay, database, redis_url, workers, grace) as service:
            app[SERVICE_KEY] = service
            yield

    app.cleanup_ctx.append(lifetime)
