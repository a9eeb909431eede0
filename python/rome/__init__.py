"""ROME from Python: the systems framework, solvers, and the stepping-stones, walking and hopping runs (docs/python.md).

Build-tree use: PYTHONPATH=<build>/python /usr/bin/python3 -c "import rome".
"""
from . import _rome
from ._rome import *  # noqa: F401,F403


class _NoInstanceDict(type(_rome.LeafSystem)):
    """Gives every Python subclass of LeafSystem `__slots__ = ()` unless it declares its own.

    Attributes set on such an instance live in the dictionary of the C++ base (pybind11's dynamic_attr). A second,
    Python-managed instance dictionary would be visited twice by the garbage collector under pybind11 2.10 and
    Python 3.11, which then never frees a leaf that is part of a reference cycle, such as the one between a diagram and
    its systems (python/bindings.h).
    """

    def __new__(mcls, name, bases, namespace, **kwargs):
        namespace.setdefault("__slots__", ())
        return super().__new__(mcls, name, bases, namespace, **kwargs)


class LeafSystem(_rome.LeafSystem, metaclass=_NoInstanceDict):
    __doc__ = _rome.LeafSystem.__doc__
