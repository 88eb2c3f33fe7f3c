"""``celtstone serve``: the live explorer as a local web page (Panel)."""

from __future__ import annotations

import argparse
import sys

from celtstone.errors import ParameterError

LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1")
DEFAULT_PORT = 5006


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone serve``."""
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default 127.0.0.1: this machine only; another "
        "address lets other machines open the page)",
    )
    parser.add_argument(
        "--port", default=str(DEFAULT_PORT), help=f"port, 1 to 65535 (default {DEFAULT_PORT})"
    )
    parser.add_argument("--no-browser", action="store_true", help="do not open a browser")


def _port(text: str) -> int:
    allowed = "a whole number in [1, 65535]"
    try:
        port = int(text)
    except ValueError:
        raise ParameterError("port", text, allowed) from None
    if not 1 <= port <= 65535:
        raise ParameterError("port", text, allowed)
    return port


def handle(args: argparse.Namespace) -> int:
    """Serve the explorer until Ctrl-C (exit 130) or SIGTERM (exit 143).

    Nothing runs beside the server while the first page is built: the page's first run
    starts once the browser shows the page (its controls answer before its verdict), and
    that run loads the compiled kernels from numba's cache, which the other models share.
    """
    from celtstone.explorer import require_panel

    port = _port(args.port)
    require_panel()
    host = args.host
    if host not in LOCAL_HOSTS:
        print(
            f"celtstone: serving on {host}:{port}: other machines that reach this address "
            "can open the explorer and start runs on this machine",
            file=sys.stderr,
        )
    print("celtstone: starting the explorer (loading Panel) …", file=sys.stderr)
    import panel as pn

    from celtstone.explorer.app import Explorer

    def page() -> object:
        return Explorer().layout

    shown = "localhost" if host in LOCAL_HOSTS else host
    origins = ["*"] if host not in LOCAL_HOSTS else [f"localhost:{port}", f"127.0.0.1:{port}"]
    print(f"celtstone explorer at http://{shown}:{port}/ (Ctrl-C stops it)", file=sys.stderr)
    pn.serve(
        {"/": page},
        port=port,
        address=host,
        websocket_origin=origins,
        show=not args.no_browser,
        title="celtstone explorer",
        threaded=False,
        print=False,
    )
    return 0
