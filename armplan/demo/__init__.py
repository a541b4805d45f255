"""``armplan demo``: the paper's human-robot collaboration task, end to end.

- ``handover_task.json``: the task, phase by phase, as wrist targets.
- :mod:`armplan.demo.task`: reads a task file, makes its ``PlanRequest``.
- :mod:`armplan.demo.stack`: every process, started in order, stopped for sure.
- :mod:`armplan.demo.session`: plan through the planner service, play
  through the bridge, write the files.
- :mod:`armplan.demo.outputs`: trajectory, Choregraphe and Python exports,
  report.
- :mod:`armplan.demo.summary`: the printed summary.
"""

from armplan.demo.session import DemoOptions, DemoResult, run_demo
from armplan.demo.summary import summary_lines
from armplan.demo.task import DEFAULT_TASK, Task, load_task

__all__ = [
    "DEFAULT_TASK",
    "DemoOptions",
    "DemoResult",
    "Task",
    "load_task",
    "run_demo",
    "summary_lines",
]
