"""Which user a configuration logs in as, and the check that it is the process's own.

On the secured router (config/secure/router.json5) each process logs in with
its own user (``transport/auth/usrpwd/user`` in its client file), and the
access rules let that user do its process's part only. A process started with
another user's file would still connect and say it is ready, yet the router
would drop what it may not do: a bridge with the client's file plays
trajectories while nobody receives its frames, an ik service with timing's
file holds no token and answers nobody. So every process checks the login of
its file at start, before it connects. A file without a login (the unsecured
set) passes: there is no user to be wrong.
"""

from __future__ import annotations

import json

import zenoh

from shared.bus.config import BusConfig
from shared.bus.zenoh_config import client_config
from shared.errors import WrongLoginError

#: Where a client's Zenoh configuration holds its user name.
USER_SETTING = "transport/auth/usrpwd/user"


def login_user(config: BusConfig) -> str | None:
    """The user ``config`` logs in as, ``None`` if it has no login."""
    try:
        user = json.loads(client_config(config).get_json(USER_SETTING))
    except zenoh.ZError:
        return None
    return None if user is None else str(user)


def check_login(config: BusConfig, user: str) -> None:
    """Refuse ``config`` if it logs in as another user than ``user``.

    Args:
        config: The process's bus settings.
        user: The process's own user, e.g. ``"bridge"``.

    Raises:
        WrongLoginError: naming the file, the expected and the given user.
    """
    given = login_user(config)
    if given is not None and given != user:
        raise WrongLoginError(source=config.source, expected=user, given=given)
