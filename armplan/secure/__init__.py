"""A secured Zenoh for armplan: TLS, a user and password per process, access control.

- ``certificates.py``: a certificate authority and the router's certificate
  (with the ``openssl`` command).
- ``passwords.py``: one random password per user, in Zenoh's dictionary file.
- ``bundle.py``: ``armplan certs --out DIR``: everything a secured router and
  its processes need, in one folder.
- ``acl.py``: the router's access rules, read back: may this user do that?

The router's configuration, access rules included, is
``config/secure/router.json5``; ``docs/services.md`` explains it.
"""

from armplan.secure.acl import AccessControl
from armplan.secure.bundle import TEMPLATE, Bundle, write_bundle
from armplan.secure.errors import SecureSetupError

__all__ = ["TEMPLATE", "AccessControl", "Bundle", "SecureSetupError", "write_bundle"]
