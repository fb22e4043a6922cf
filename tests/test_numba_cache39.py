"""numba's on-disk cache and the kernels compiled without wrappers (issue 27 §3, session 39).

``_jit.compile_together(..., internal=...)`` builds the functions only compiled code calls
without the wrappers Python calls through. numba's cache keys a function by its file, name, code
and argument types, not by its wrappers: a function compiled so in one namespace and with its
wrappers in another shares one cache entry, and the process that loads the wrapperless one and
calls it from Python crashes. The flexible rotors' journal model compiles the film kernel
(``_fast._film_force``) and calls it from Python; the rigid model had it in ``INTERNAL``: a
flexible journal simulation after a rigid one, in a new process, ended in a segmentation fault.
"""

from __future__ import annotations

from rotordyn_modal.simulation import _fast, flexible_journal


def test_no_function_the_journal_model_compiles_is_built_without_its_wrappers_elsewhere():
    compiled_here = {f.__name__ for f in flexible_journal.FILM_FUNCTIONS}
    assert "_film_force" in compiled_here and compiled_here <= set(_fast.FUNCTIONS) | {"film_load"}
    assert not compiled_here & set(_fast.INTERNAL)
