"""Plain Python functions compiled by numba together, so that they call each other in machine code.

numba compiles a call to another function only when that function is itself compiled and
found among the caller's globals. The kernels are written as plain functions of their own
modules (the reference path, readable and tested without numba); :func:`compile_together`
rebinds each one's code to a namespace whose globals are the compiled versions of the others.
numba's on-disk cache keys a function by its source file, qualified name and bytecode, none of
which the rebinding changes, so a second process loads the machine code instead of compiling.
"""

from __future__ import annotations

import types


def numba_or_none():
    """The ``numba`` module, or None when it is not installed."""
    try:
        import numba
    except ImportError:
        return None
    return numba


def compile_together(functions, names, module, inlined=(), internal=()) -> dict:
    """Compile ``functions`` by numba (cached on disk), each calling the others compiled.

    Parameters
    ----------
    functions : iterable of function
        Plain Python functions in the subset numba compiles, each found by its ``__name__``.
    names : dict
        The other globals their code looks up (``{"np": numpy}``, module constants,
        functions compiled elsewhere).
    module : str
        The ``__name__`` of the namespace (the module the functions are taken from), which
        numba reports in its errors.
    inlined : collection of str
        Names of functions numba inlines into their callers (``inline="always"``); the others
        stay calls.
    internal : collection of str
        Names of functions called only by the others: compiled without the wrappers that let
        Python call them (machine code numba would otherwise generate, optimise and cache for each).

    Returns
    -------
    dict
        The namespace: ``names``, ``__name__`` and each function's numba dispatcher by name.
        Each is compiled on its first call, with the globals the namespace holds then (an
        entry may be replaced before that).
    """
    import numba

    namespace = {"__name__": module, **names}
    for function in functions:
        name = function.__name__
        rebound = types.FunctionType(function.__code__, namespace, name, function.__defaults__)
        inline = "always" if name in inlined else "never"
        bare = name in internal
        namespace[name] = numba.njit(cache=True, inline=inline, no_cpython_wrapper=bare,
                                     no_cfunc_wrapper=bare)(rebound)
    return namespace
