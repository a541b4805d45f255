"""``armplan faults``: kill, restart and feed bad inputs to the running system.

Every scenario runs the real processes on free ``127.0.0.1`` ports and
sorts each request it sends into succeeded, failed with a clear (typed)
error, failed with an unclear one (``internal_error``), or lost (no answer
within its timeout); a process that exits without being killed is a crash.

- ``outcome.py``: one request sent, and how it ended (:func:`send`).
- ``tally.py``: one scenario's counts (:class:`Tally`), and what it failed to show.
- ``traffic.py``: client threads sending requests over one bus.
- ``requests.py``: a valid request for every route (traffic, templates).
- ``strategies.py``: hypothesis strategies that spoil a valid request.
- ``system.py``: every process, started, killed and restarted by name.
- ``out_folder.py``: the files it writes, and an earlier run's refused.
- ``kill_restart.py``: a service, the bridge or the router killed in traffic.
- ``recorder_kill.py``: the recorder killed mid-session.
- ``burst.py``: many plan requests at once.
- ``bad_input.py``: bad inputs against one queryable.
- ``suite.py``: every scenario in turn (:func:`run_suite`).
- ``table.py``: the table, and whether the suite passed (:func:`passed`).

See docs/faults.md.
"""

from armplan.faults.outcome import Call, Outcome, Result, send
from armplan.faults.suite import SuiteOptions, run_suite
from armplan.faults.table import json_report, passed, rich_table
from armplan.faults.tally import Tally

__all__ = [
    "Call",
    "Outcome",
    "Result",
    "SuiteOptions",
    "Tally",
    "json_report",
    "passed",
    "rich_table",
    "run_suite",
    "send",
]
