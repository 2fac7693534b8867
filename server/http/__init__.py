"""The aiohttp application: the app and its settings (`app`), the thin `/api/` handlers and the
route table that drives the router and the OpenAPI description (`api`, `openapi`), the pages
and their data (`pages`, `diagrams`), `billiards serve` (`serve`) and its collector policy."""
