"""Who may see and drive the web viewer: whoever holds the token in its printed URL (as Jupyter does).

The viewer's server answers HTTP (the page) and websockets (the scene, the buttons) on one port.
Every request must carry the token: as ``?token=`` in its URL, or in the cookie the page receives
when it is opened with the token (the page's own websocket does not repeat the URL's query, and a
reload keeps working). Anything else gets ``403`` before viser sees it: no page, no scene, no
buttons. The cookie is ``HttpOnly`` and ``SameSite=Strict``, so neither another site's script nor a
page of another origin can use it.

viser has no hook for this; the check is put in front of viser's own request handler
(``process_request`` of ``websockets.asyncio.server.serve``, which viser calls as its server starts).
:func:`start_gated_viser` fails closed: if viser starts its server some other way (a viser version
this was not written for), the viewer is refused rather than opened to everyone.
"""

from __future__ import annotations

import hmac
import http
import http.cookies
import os
import secrets
import threading
import urllib.parse
from collections.abc import Callable
from typing import Any

__all__ = ["TOKEN_ENV", "UngatedServerError", "new_token", "start_gated_viser", "token_gate"]

TOKEN_ENV = "SIMLAB_VIEWER_TOKEN"
"""A token to use instead of a random one (scripts that connect to the viewer they start)."""

_patch_lock = threading.Lock()  # one gated server starts at a time: the hook below is process-wide while it does


class UngatedServerError(RuntimeError):
    """viser started its server without the token check (a viser version simlab does not know)."""


def new_token() -> str:
    """``$SIMLAB_VIEWER_TOKEN`` if set, else 32 random bytes, URL-safe."""
    return os.environ.get(TOKEN_ENV) or secrets.token_urlsafe(32)


def _given_token(request: Any, cookie_name: str) -> tuple[str | None, bool]:
    """The token a request carries, and whether it came in its URL (then the page gets the cookie)."""
    query = urllib.parse.parse_qs(urllib.parse.urlsplit(request.path).query)
    if query.get("token"):
        return query["token"][0], True
    cookies = http.cookies.SimpleCookie()
    try:
        cookies.load(request.headers.get("Cookie", ""))
    except http.cookies.CookieError:
        return None, False
    return (cookies[cookie_name].value if cookie_name in cookies else None), False


def token_gate(token: str, cookie_name: str, inner: Callable | None) -> Callable:
    """A ``process_request`` that answers 403 unless the request carries ``token``, else hands it to
    ``inner`` (viser's: the page's files; None for a websocket, which then opens)."""

    def process_request(connection: Any, request: Any) -> Any:
        given, in_url = _given_token(request, cookie_name)
        if given is None or not hmac.compare_digest(given.encode(), token.encode()):
            return connection.respond(
                http.HTTPStatus.FORBIDDEN, "simlab web viewer: open the URL it printed, with its token.\n"
            )
        response = inner(connection, request) if inner is not None else None
        if response is not None and in_url:
            response.headers["Set-Cookie"] = f"{cookie_name}={token}; HttpOnly; SameSite=Strict; Path=/"
        return response

    return process_request


def start_gated_viser(host: str, port: int, token: str, **kwargs: Any):
    """A ``viser.ViserServer`` on ``host:port`` whose every request must carry ``token``.

    Raises:
        UngatedServerError: viser did not start its server through the hook the check sits on.
    """
    import viser
    import websockets.asyncio.server as ws_server

    cookie_name = f"simlab-viewer-{port}"  # cookies are per host, not per port: one per viewer
    plain_serve = ws_server.serve
    gated = []

    class _GatedServe(plain_serve):  # type: ignore[misc, valid-type]
        def __init__(self, handler: Any, *args: Any, process_request: Callable | None = None, **kw: Any):
            gated.append(True)
            super().__init__(handler, *args, process_request=token_gate(token, cookie_name, process_request), **kw)

    with _patch_lock:
        ws_server.serve = _GatedServe  # viser's server thread calls it before ViserServer() returns
        try:
            server = viser.ViserServer(host=host, port=port, **kwargs)
        finally:
            ws_server.serve = plain_serve
    if not gated:
        server.stop()
        raise UngatedServerError(
            f"viser {viser.__version__} started its server without simlab's token check; "
            'install the viser version simlab supports: pip install "simlab[viewer]"'
        )
    return server
