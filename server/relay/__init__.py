"""An nchan-like publish/subscribe relay on aiohttp.

It carries messages between clients and knows nothing of billiards. `backend` holds the
storage interface (memory or Redis), the transports (`publisher`, `websocket`, `eventsource`,
`longpoll`) speak nchan's wire protocol, and `routes` mounts them on an aiohttp application.
"""
