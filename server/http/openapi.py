"""The OpenAPI description of the game service's `/api/` endpoints, built from `api.ROUTES`.

Schemas come from the pydantic models themselves (requests in validation mode, answers in
serialisation mode), so the description cannot drift from what the handlers parse and send.
The relay describes its own endpoints at `/openapi.json`.
"""

from __future__ import annotations

import re
from functools import cache
from typing import Any

from pydantic import BaseModel
from pydantic.json_schema import models_json_schema

from server.http.api import ROUTES, Route
from server.protocol.errors import STATUS, ErrorCode
from server.protocol.models import ApiError

_REF = "#/components/schemas/{model}"
_PARAM = re.compile(r"\{(\w+):([^{}]*(?:\{\d+(?:,\d+)?\}[^{}]*)*)\}")


def _ref(model: type[BaseModel]) -> dict[str, str]:
    return {"$ref": _REF.format(model=model.__name__)}


def _json(model: type[BaseModel], description: str) -> dict[str, Any]:
    return {"description": description, "content": {"application/json": {"schema": _ref(model)}}}


def _refusals(route: Route) -> dict[str, Any]:
    codes = {ErrorCode.UNAVAILABLE, *route.refusals}
    if route.auth:
        codes.add(ErrorCode.UNAUTHORIZED)
    if route.body is not None:
        codes |= {ErrorCode.BAD_REQUEST, ErrorCode.BODY_TOO_LARGE, ErrorCode.ILLEGAL_INPUT}
        codes |= {ErrorCode.UNSUPPORTED_MEDIA_TYPE, ErrorCode.REQUEST_TIMEOUT}
    by_status: dict[int, list[str]] = {}
    for code in sorted(codes):
        by_status.setdefault(STATUS[code], []).append(code.value)
    return {str(s): _json(ApiError, "refused: " + ", ".join(c)) for s, c in by_status.items()}


def _operation(route: Route) -> dict[str, Any]:
    operation: dict[str, Any] = {
        "summary": route.summary,
        "operationId": route.handler.__name__,
        "responses": {
            **{str(s): _json(m, m.__name__) for s, m in route.answers.items()},
            **_refusals(route),
        },
    }
    if route.auth:
        operation["security"] = [{"bearer": []}]
    if route.body is not None:
        operation["requestBody"] = {
            "required": True,
            "description": f"at most {route.max_body} bytes",
            "content": {"application/json": {"schema": _ref(route.body)}},
        }
    parameters = [
        {
            "name": name,
            "in": "path",
            "required": True,
            "schema": {"type": "string", "pattern": f"^(?:{p})$"},
        }
        for name, p in _PARAM.findall(route.path)
    ]
    if parameters:
        operation["parameters"] = parameters
    return operation


@cache
def openapi_document() -> dict[str, Any]:
    models: set[tuple[type[BaseModel], str]] = {(ApiError, "serialization")}
    for route in ROUTES:
        models |= {(m, "serialization") for m in route.answers.values()}
        if route.body is not None:
            models.add((route.body, "validation"))
    _, schemas = models_json_schema(sorted(models, key=lambda m: m[0].__name__), ref_template=_REF)
    paths: dict[str, dict[str, Any]] = {}
    for route in ROUTES:
        path = _PARAM.sub(lambda match: "{" + match[1] + "}", route.path)
        paths.setdefault(path, {})[route.method.lower()] = _operation(route)
    return {
        "openapi": "3.1.0",
        "info": {"title": "billiards game service", "version": "1.0.0"},
        "components": {
            "schemas": schemas["$defs"],
            "securitySchemes": {"bearer": {"type": "http", "scheme": "bearer"}},
        },
        "paths": paths,
    }
