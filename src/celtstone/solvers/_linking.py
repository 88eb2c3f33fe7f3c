"""Calls from one compiled driver to another through the callee's address (decisions §39).

When a numba function calls another, numba links the callee's code into the caller and
optimises and generates machine code for the whole again. The run loop
``driver.integrate`` is large (about 2.5 MB of machine code), and the stick–slip loop
``phases.run_phases`` and the sweep's ``batch._batch`` each held a copy of it: their
first compile was almost all LLVM redoing that work (58 s of 59 s for ``run_phases``).

``address_call(dispatcher)`` returns ``call(link, arguments)``, compiled code that calls
the dispatcher's overload for the types of the tuple ``arguments`` at the address in
``link``, as numba's own call would but without linking its code. ``link`` is the pair
(address, signature key) that :func:`link_to` makes in Python for the same arguments;
the caller passes it down as data. The key is checked before the call: a link to
another overload (a stale cache after a change of the callee's types) raises
``RuntimeError`` instead of calling code that reads its arguments differently.

A link may name an overload compiled for some arguments as constants
(``link_to(..., constants=...)``: the run loop per model and method code, whose other
codes' branches are then not compiled, ``kernels._pruning``); the call site passes
those arguments as plain ints, which the callee never reads, and declares the return
type (``address_call(..., returns=...)``) so that typing it compiles nothing. The key is
made of the argument types without their literal values, the same on both sides.

With ``NUMBA_DISABLE_JIT=1`` ``call`` calls the Python function and links are (0, 0).
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Iterable
from typing import Any, cast

import numpy as np
from numba import types
from numba._dispatcher import compute_fingerprint
from numba.core import cgutils, config
from numba.core.compiler_lock import global_compiler_lock
from numba.core.typing.typeof import Purpose, typeof
from numba.extending import intrinsic

from celtstone.kernels._pruning import CodedRecord, plain_type

NO_LINK = (0, 0)  # for a callee that a call never reaches
_LINKS: dict[tuple[Any, ...], tuple[int, int]] = {}  # link_to's, per type fingerprint
# cached_link_to's misses: the dispatcher's number of versions when it found none
_MISSES: dict[tuple[Any, ...], int] = {}
LINK_TYPE = types.UniTuple(types.int64, 2)  # (address, signature key) in compiled code
_PYTHON = bool(getattr(config, "DISABLE_JIT", 0))  # NUMBA_DISABLE_JIT=1: no compiled code


def _signature_key(argument_types: tuple[Any, ...], return_type: Any) -> int:
    """A 31-bit checksum of the overload's argument types, without literal values or
    coded record fields (``plain_type``), and its return type, the same in every process
    (numba's type names are stable)."""
    plain = tuple(plain_type(argument) for argument in argument_types)
    text = f"{plain!r}->{return_type!r}"
    return max(zlib.crc32(text.encode()) & 0x7FFFFFFF, 1)  # never NO_LINK's 0


def _overload(dispatcher: Any, argument_types: tuple[Any, ...]) -> Any:
    """The dispatcher's compile result for these argument types, loaded from numba's
    cache or compiled now."""
    dispatcher.compile(argument_types)
    return dispatcher.overloads[argument_types]


def compile_for(dispatcher: Any, arguments: tuple[Any, ...]) -> None:
    """Compile ``dispatcher`` for the types of ``arguments`` (Python values), or load it
    from numba's cache, in this thread: a later call with them only runs."""
    if not _PYTHON and hasattr(dispatcher, "compile"):  # else a plain function
        _overload(dispatcher, tuple(typeof(value, Purpose.argument) for value in arguments))


def _record_codes(arguments: tuple[Any, ...], fields: tuple[str, ...]) -> tuple[Any, ...]:
    """Per argument, the (name, value) pairs of its ``fields`` if it is a record, else
    (); () without ``fields`` (the key of a link without coded fields)."""
    if not fields:
        return ()
    return tuple(
        tuple((name, int(value[name])) for name in fields)
        if isinstance(value, (np.void, np.record))
        else ()
        for value in arguments
    )


def _link_key(
    dispatcher: Any, arguments: tuple[Any, ...], constants: tuple[int, ...], fields: tuple[str, ...]
) -> tuple[Any, tuple[Any, ...]]:
    """(the key of a link in ``_LINKS``, None where numba has no type fingerprint for a
    value; the record arguments' codes, ``_record_codes``)."""
    codes = _record_codes(arguments, fields)
    values = (tuple(int(arguments[position]) for position in constants), codes)
    try:
        return (dispatcher, compute_fingerprint(arguments), constants, values), codes
    except NotImplementedError:
        return None, codes


def link_to(
    dispatcher: Any,
    arguments: tuple[Any, ...],
    constants: tuple[int, ...] = (),
    fields: tuple[str, ...] = (),
) -> tuple[int, int]:
    """(address, signature key) of ``dispatcher`` compiled for the types of
    ``arguments`` (Python values, as a call from Python would pass them); the
    arguments at the positions ``constants`` (ints) as compile-time constants
    (numba literals), and a record argument's ``fields`` (int codes) too
    (``kernels._pruning.CodedRecord``), so that only their branches are compiled.

    Kept per numba type fingerprint of ``arguments`` (numba's own cheap key, as its
    dispatcher keeps its types) and the constants' values: typing a parameter record
    takes about 0.5 ms.
    """
    if _PYTHON:
        return NO_LINK
    fingerprint, codes = _link_key(dispatcher, arguments, constants, fields)
    if fingerprint is None:  # a value numba has no fingerprint for: typed each call
        return _new_link(dispatcher, arguments, constants, codes)
    link = _LINKS.get(fingerprint)
    if link is None:
        link = _LINKS[fingerprint] = _new_link(dispatcher, arguments, constants, codes)
    return link


def made_link(
    dispatcher: Any,
    arguments: tuple[Any, ...],
    constants: tuple[int, ...] = (),
    fields: tuple[str, ...] = (),
) -> tuple[int, int] | None:
    """The link that :func:`link_to` made in this process for these arguments,
    constants and record fields, else None: nothing is compiled or loaded."""
    if _PYTHON:
        return NO_LINK
    fingerprint, _ = _link_key(dispatcher, arguments, constants, fields)
    return None if fingerprint is None else _LINKS.get(fingerprint)


def cached_link_to(
    dispatcher: Any,
    arguments: tuple[Any, ...],
    constants: tuple[int, ...] = (),
    fields: tuple[str, ...] = (),
) -> tuple[int, int] | None:
    """``link_to(dispatcher, arguments, constants, fields)`` if that version is compiled
    in this process or in numba's on-disk cache (then loaded), else None: nothing is
    compiled."""
    if _PYTHON:
        return NO_LINK
    fingerprint, codes = _link_key(dispatcher, arguments, constants, fields)
    link = _LINKS.get(fingerprint) if fingerprint is not None else None
    if link is not None:
        return link
    if fingerprint is not None and _MISSES.get(fingerprint) == len(dispatcher.overloads):
        return None  # not in the cache, and nothing compiled since: typed once
    argument_types = _argument_types(arguments, constants, codes)
    if argument_types not in dispatcher.overloads:
        with global_compiler_lock:  # as numba's own load, in ``Dispatcher.compile``
            loaded = dispatcher._cache.load_overload(argument_types, dispatcher.targetctx)
            if loaded is None:
                if fingerprint is not None:
                    _MISSES[fingerprint] = len(dispatcher.overloads)
                return None
            dispatcher.targetctx.insert_user_function(
                loaded.entry_point, loaded.fndesc, [loaded.library]
            )
            dispatcher.add_overload(loaded)
    return link_to(dispatcher, arguments, constants, fields)


def _argument_types(
    arguments: tuple[Any, ...], constants: tuple[int, ...], codes: tuple[Any, ...]
) -> tuple[Any, ...]:
    """The numba types of ``arguments`` for a link: those at the positions ``constants``
    as literals, a record with ``codes`` (``_record_codes``) as a ``CodedRecord``."""
    return tuple(
        types.literal(int(value))
        if position in constants
        else CodedRecord(typeof(value, Purpose.argument), codes[position])
        if codes and codes[position]
        else typeof(value, Purpose.argument)
        for position, value in enumerate(arguments)
    )


def _new_link(
    dispatcher: Any,
    arguments: tuple[Any, ...],
    constants: tuple[int, ...],
    codes: tuple[Any, ...],
) -> tuple[int, int]:
    argument_types = _argument_types(arguments, constants, codes)
    overload = _overload(dispatcher, argument_types)
    address = overload.library.get_pointer_to_function(overload.fndesc.llvm_func_name)
    if not address:
        raise RuntimeError(f"no compiled code for {dispatcher.py_func.__qualname__}")
    return address, _signature_key(argument_types, overload.signature.return_type)


def address_call(dispatcher: Any, returns: Any = None) -> Callable[..., Any]:
    """``call(link, arguments)``: ``dispatcher(*arguments)`` at ``link``'s address.

    ``returns``: the callee's numba return type, for a link to an overload with
    constant arguments (``link_to``'s ``constants``); typing the call then compiles
    nothing. Without it the call's typing compiles (or loads) the overload for the
    arguments' types, for its return type.
    """
    if _PYTHON:

        def call_python(link: tuple[int, int], arguments: tuple[Any, ...]) -> Any:
            return dispatcher(*arguments)

        return call_python

    name = dispatcher.py_func.__qualname__

    @intrinsic
    def call(typingctx: Any, link: Any, arguments: Any) -> Any:
        if link != LINK_TYPE or not isinstance(arguments, types.BaseTuple):
            return None  # numba reports the call's types as not supported
        argument_types = tuple(cast(Iterable[Any], arguments))  # its member types
        if returns is None:
            return_type = _overload(dispatcher, argument_types).signature.return_type
        else:
            return_type = returns
        key = _signature_key(argument_types, return_type)

        def codegen(context: Any, builder: Any, signature: Any, values: Any) -> Any:
            link_value, arguments_value = values
            address = builder.extract_value(link_value, 0)
            link_key = builder.extract_value(link_value, 1)
            wrong = builder.icmp_signed("!=", link_key, link_key.type(key))
            with cgutils.if_unlikely(builder, wrong):
                context.call_conv.return_user_exc(
                    builder, RuntimeError, (f"{name}: a link to another compiled version",)
                )
            function_type = context.call_conv.get_function_type(return_type, argument_types)
            function = builder.inttoptr(address, function_type.as_pointer())
            argument_values = cgutils.unpack_tuple(builder, arguments_value, len(argument_types))
            status, result = context.call_conv.call_function(
                builder, function, return_type, argument_types, argument_values
            )
            with cgutils.if_unlikely(builder, status.is_error):
                context.call_conv.return_status_propagate(builder, status)
            return result

        return return_type(link, arguments), codegen

    return call
