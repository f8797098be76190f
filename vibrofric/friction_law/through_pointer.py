"""The law called through a function pointer: loops compiled once for every law.

A loop specialized for a law (specialize.py) has the law's update linked into its
machine code, so a law never seen before compiles its loops first: 5-10 s for the
reduced FE loop and its contact iteration (docs/first-answer.md). Here the loops'
``law_update`` and ``law_energy`` are instead calls through a pointer read from a
process-wide slot (``vibrofric_law_update_slot``, ``vibrofric_law_energy_slot``,
two symbols registered with LLVM before any loop is loaded): the loop is compiled
once for every law and cached by numba like any other function, and a new law
compiles its own update alone, for the one signature below (UPDATE, ENERGY), and
its address is written to the slot before each call of a loop (``LawPointers``).

The call goes through numba's C-ABI wrapper of the law's compiled function (the
same wrapper numba's first-class functions call: numba.experimental.function_type),
which LLVM cannot inline into the loop: the law's calls cost about twice what they
cost linked (docs/first-answer.md), and an exception raised in the law is not
propagated by the wrapper but written to ``sys.unraisablehook`` (``caught``).

numba's first-class functions (a loop argument of ``types.FunctionType``) give the
same call, but as an argument of every loop and of every law kernel between the
loop and the law; the slot keeps the loops' signatures as they are.
"""

import ctypes
import sys
import threading
from contextlib import contextmanager

from llvmlite import binding as llvm
from llvmlite import ir
from numba import types
from numba.core import errors
from numba.extending import intrinsic

STATE = types.Array(types.float64, 1, "C")  # a node's state, and the law's parameters
UPDATE = types.UniTuple(types.float64, 2)(types.float64, types.float64, types.float64,
                                          types.float64, types.float64, types.float64,
                                          STATE, STATE, types.float64)
ENERGY = types.float64(STATE, STATE, types.float64)

_SLOT_NAMES = ("vibrofric_law_update_slot", "vibrofric_law_energy_slot")
_slots = (ctypes.c_void_p * len(_SLOT_NAMES))()
for _index, _name in enumerate(_SLOT_NAMES):
    llvm.add_symbol(_name, ctypes.addressof(_slots) + _index * ctypes.sizeof(ctypes.c_void_p))
_slots_lock = threading.Lock()


def _typed_as(given, wanted, name: str):
    """The call's argument types, checked against the pointer's signature ``wanted``:
    numbers are converted to float64; an array must be ``wanted``'s exactly."""
    for position, (have, want) in enumerate(zip(given, wanted.args)):
        if isinstance(want, types.Array) and have != want:
            raise errors.TypingError(f"{name}: argument {position} is {have}, the law's "
                                     f"pointer takes {want}")
        if not isinstance(want, types.Array) and not isinstance(have, types.Number):
            raise errors.TypingError(f"{name}: argument {position} is {have}, not a number")
    return wanted.return_type(*given)


def _call_through(slot_name: str, wanted):
    """Codegen: the call's arguments converted to ``wanted``'s types, then a call of the
    function whose address the slot ``slot_name`` holds."""
    def codegen(context, builder, signature, args):
        values = [context.cast(builder, value, have, want)
                  for value, have, want in zip(args, signature.args, wanted.args)]
        function_type = ir.FunctionType(context.get_value_type(wanted.return_type),
                                        [context.get_value_type(t) for t in wanted.args])
        module = builder.module
        slot = module.globals.get(slot_name)
        if slot is None:
            slot = ir.GlobalVariable(module, function_type.as_pointer(), slot_name)
            slot.linkage = "external"
        return builder.call(builder.load(slot), values)
    return codegen


@intrinsic
def law_update(typingctx, slip_x, slip_y, free_x, free_y, normal_force, area_share, state,
               params, dt):
    """The law's update (contract.py) through the update slot's pointer."""
    given = (slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt)
    return (_typed_as(given, UPDATE, "law_update"), _call_through(_SLOT_NAMES[0], UPDATE))


@intrinsic
def law_energy(typingctx, state, params, area_share):
    """The law's stored energy (contract.py) through the energy slot's pointer."""
    return (_typed_as((state, params, area_share), ENERGY, "law_energy"),
            _call_through(_SLOT_NAMES[1], ENERGY))


def _wrapper_address(dispatcher, sig) -> int:
    """The address of numba's C-ABI wrapper of ``dispatcher`` compiled for ``sig``."""
    dispatcher.compile(sig.args)
    result = dispatcher.overloads[sig.args]
    return result.library.get_pointer_to_function(result.fndesc.llvm_cfunc_wrapper_name)


class LawPointers:
    """A law's update and stored energy compiled for UPDATE and ENERGY (numba
    dispatchers: specialize._called), and their wrappers' addresses."""

    def __init__(self, update, stored_energy):
        self.addresses = (_wrapper_address(update, UPDATE),
                          _wrapper_address(stored_energy, ENERGY))

    def calling(self, function):
        """``function`` (a loop compiled with the pointer calls) called with this law in
        the slots; the slots are held for the call (one law at a time in a process)."""
        def run(*args):
            with _slots_lock, caught():
                _slots[0], _slots[1] = self.addresses
                return function(*args)
        return run


class LawRaised(Exception):
    """An exception the law raised through the pointer (``caught``)."""


@contextmanager
def caught():
    """Raise, after the call, the first exception the law raised during it.

    numba's C-ABI wrapper cannot hand an exception to its caller: it writes it to
    ``sys.unraisablehook`` and returns, and the loop goes on with what the law
    returned. Collected here, the first one is raised as LawRaised (its cause the
    law's exception) once the loop's call (a chunk of steps: core.chunks) ends."""
    raised = []
    hook = sys.unraisablehook

    def collect(unraisable):
        if unraisable.exc_value is not None:
            raised.append(unraisable.exc_value)

    sys.unraisablehook = collect
    try:
        yield
    finally:
        sys.unraisablehook = hook
    if raised:
        raise LawRaised(f"{type(raised[0]).__name__}: {raised[0]}") from raised[0]
