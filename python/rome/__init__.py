"""ROME from Python: the systems framework, solvers, and the stepping-stones, walking and hopping runs (docs/python.md).

Build-tree use: PYTHONPATH=<build>/python /usr/bin/python3 -c "import rome".
"""
from ._rome import *  # noqa: F401,F403
from ._rome import __doc__ as _native_doc  # noqa: F401
