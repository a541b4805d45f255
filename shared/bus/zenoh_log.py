"""Zenoh's own log in the router: warnings, and refused connections when secured.

Without it, a router refused logins and TLS handshakes without a trace.
Zenoh logs a refused login ("UsrPwd extension - Recv OpenSyn. Invalid
password." or "Invalid user.") only at debug level, on the target of
:data:`HANDSHAKE_TARGET`, whose debug lines hold the handshake's error or the
accepted link (addresses, Zenoh ids), never a password; a refused TLS
handshake (a client trusting another CA, plain TCP) is a Zenoh warning. So
the router logs warnings, and for a secured configuration that one target at
debug. Zenoh's debug level in general prints the whole configuration, a
``--connect`` router's password included: ``RUST_LOG`` is therefore not read
(it is removed from this process's environment before the log starts).
Zenoh writes these lines to stdout in its own format, coloured only on a
terminal (``NO_COLOR`` otherwise: a log file got escape codes). A query
whose caller left before its answer (the caller's own timeout, which it is
told of) is a Zenoh warning too, three lines each: only that target's
errors are logged (:data:`QUERIES_TARGET`).
"""

from __future__ import annotations

import os
import sys

import zenoh

#: Where Zenoh logs (at debug) each handshake the router accepts or refuses.
HANDSHAKE_TARGET = "zenoh_transport::unicast::establishment::accept"
#: Where Zenoh warns that a query's caller left before its answer ("Didn't
#: receive final reply for query", "Query not found"): a client's own
#: timeout, which it is told of; only its errors are logged.
QUERIES_TARGET = "zenoh::net::routing::dispatcher::queries"
#: The filter for an unsecured router: Zenoh's warnings and errors.
PLAIN_FILTER = f"warn,{QUERIES_TARGET}=error"
#: The filter for a secured one: also every accepted and refused handshake.
SECURED_FILTER = f"{PLAIN_FILTER},{HANDSHAKE_TARGET}=debug"


def start_zenoh_log(secured: bool) -> str:
    """Start Zenoh's log for a router (once per process); returns the filter.

    Args:
        secured: Whether the router checks logins or speaks TLS.
    """
    os.environ.pop("RUST_LOG", None)  # its debug would print passwords
    if not sys.stdout.isatty():  # colour codes in a log file are noise
        os.environ["NO_COLOR"] = "1"
    chosen = SECURED_FILTER if secured else PLAIN_FILTER
    zenoh.init_log_from_env_or(chosen)
    return chosen
