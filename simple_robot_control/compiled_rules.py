"""
Plain-Python rules compiled by numba as they are: one source for Python and compiled code.

numba compiles a function that calls another only if it knows the callee: register_jitable
lets it compile these from their source wherever compiled code calls them, and compiled()
makes a compiled copy of a rule for callers of its own (the simulator's step, the learning
task's pass). Imported only by compiled code: the light tools never load numba.
"""

from typing import Callable

from numba import njit
from numba.extending import register_jitable
from simple_robot_control.pose import wrap_number

register_jitable(wrap_number)


def compiled(rule: Callable) -> Callable:
    """Return rule (a plain-Python function of numbers) compiled, its machine code cached."""
    return njit(cache=True)(rule)
