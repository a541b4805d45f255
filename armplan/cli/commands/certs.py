"""``armplan certs``: certificates, passwords and configs for a secured Zenoh."""

from __future__ import annotations

import argparse
import sys

from armplan.secure import write_bundle
from armplan.secure.bundle import (
    DEFAULT_ENDPOINT,
    TEMPLATE,
    TEMPLATE_ENDPOINT,
    TEMPLATE_NAMESPACE,
    TEMPLATE_PATHS,
)
from armplan.secure.certificates import DAYS

ORDER = 83
HELP = "write TLS certificates, passwords and Zenoh configs for a secured router"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``certs``."""
    parser = commands.add_parser(
        "certs",
        help=HELP,
        description=f"{HELP}. The router's access rules: "
        f"config/secure/{TEMPLATE.name}; see docs/services.md#security.",
    )
    parser.add_argument("--out", required=True, metavar="DIR", help="folder to write")
    parser.add_argument(
        "--endpoint",
        metavar="ENDPOINT",
        help=f"the router's TLS endpoint (default {DEFAULT_ENDPOINT}; "
        f"--compose: {TEMPLATE_ENDPOINT})",
    )
    parser.add_argument(
        "--host",
        action="append",
        default=[],
        metavar="NAME",
        help="another name or address of the router's machine for its certificate "
        "(repeatable; the endpoint's host, localhost and 127.0.0.1 are always in)",
    )
    parser.add_argument(
        "--connect",
        action="append",
        default=[],
        metavar="ENDPOINT",
        help="another machine's router to connect to, e.g. tls/192.0.2.10:7447",
    )
    parser.add_argument(
        "--paths",
        metavar="DIR",
        help="where the processes find the files (default: --out; "
        f"--compose: {TEMPLATE_PATHS}); a relative DIR is made absolute",
    )
    parser.add_argument(
        "--compose",
        action="store_true",
        help="for docker-compose.secure.yml: endpoint tls/router:7447, files in "
        f"{TEMPLATE_PATHS}",
    )
    parser.add_argument(
        "--days", type=int, default=DAYS, help="validity of new certificates [days]"
    )
    parser.add_argument(
        "--namespace",
        default=TEMPLATE_NAMESPACE,
        metavar="NS",
        help="key namespace of this router's processes, e.g. nao1 (default "
        f"{TEMPLATE_NAMESPACE}): the access rules and every client file use it",
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Write the folder and say what is in it."""
    from shared.output_paths import check_output_folder

    folder = check_output_folder(args.out)
    compose = bool(args.compose)
    # an empty value given (`--paths "$DEST"`, DEST unset) is refused, not
    # taken for the option left out
    endpoint = args.endpoint
    if endpoint is None:
        endpoint = TEMPLATE_ENDPOINT if compose else DEFAULT_ENDPOINT
    paths = args.paths
    if paths is None and compose:
        paths = TEMPLATE_PATHS
    bundle = write_bundle(
        folder,
        endpoint=endpoint,
        hosts=args.host,
        paths=paths,
        connect=args.connect,
        days=args.days,
        namespace=args.namespace,
    )
    authority = "new" if bundle.authority_created else "kept"
    out = sys.stdout
    out.write(
        f"armplan certs: wrote {bundle.directory}/ (router endpoint {endpoint}, "
        f"namespace {args.namespace})\n"
    )
    out.write(f"  ca.pem, ca.key            certificate authority ({authority})\n")
    out.write("  router.pem, router.key    the router's certificate and key\n")
    out.write("  passwords.txt             one user:password line per user\n")
    out.write(f"  {bundle.router_config.name:<25} the router's config\n")
    for user, path in bundle.clients.items():
        out.write(f"  {path.name:<25} client config of user {user}\n")
    out.write(
        f"Router:  python -m shared.bus.router --config {bundle.router_config}\n"
        f"Service: python -m services.ik --config {bundle.clients['ik']}\n"
        f"Client:  ARMPLAN_ZENOH_CONFIG={bundle.clients['client']} armplan status\n"
        "Keep ca.key off the robot's machines; passwords and keys are owner-only.\n"
        f"Renew: the router's certificate is valid {args.days} days; rerun this "
        "command (same options) before it ends and restart the router.\n"
    )
    for warning in bundle.warnings:
        sys.stderr.write(f"armplan certs: warning: {warning}\n")
    return 0
