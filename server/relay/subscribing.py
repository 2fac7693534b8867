"""Subscribing one connection's queue to all of its channels, and undoing it."""

from __future__ import annotations

import asyncio

from server.relay.backend import Subscription
from server.relay.cursor import Cursor
from server.relay.relay import Relay
from server.relay.sendqueue import SendQueue


async def subscribe_all(
    relay: Relay, channels: list[str], cursor: Cursor, queue: SendQueue
) -> list[Subscription]:
    """Subscribe `queue` to every channel, each resuming from its cursor position."""
    subscriptions: list[Subscription] = []
    try:
        for channel in channels:
            subscriptions.append(
                await relay.backend.subscribe(
                    channel, queue, cursor.positions.get(channel), relay.settings.first_message
                )
            )
    except BaseException:
        await unsubscribe_all(relay, subscriptions)
        raise
    return subscriptions


async def unsubscribe_all(relay: Relay, subscriptions: list[Subscription]) -> None:
    """End the subscriptions, even if the caller is cancelled meanwhile.

    aiohttp cancels a handler whose client has gone; the cleanup must still run to the end, or
    the channel would keep counting (and feeding) a subscriber that no longer exists.
    """

    async def unsubscribe() -> None:
        for subscription in subscriptions:
            await relay.backend.unsubscribe(subscription)

    await asyncio.shield(asyncio.ensure_future(unsubscribe()))
