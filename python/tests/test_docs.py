"""Docstring examples run, and the type stubs cover exactly the compiled module's functions and
classes."""

import ast
import doctest
import inspect
from pathlib import Path

import tessella
from tessella import _tessella


def test_docstring_examples_run():
    failures, tried = doctest.testmod(tessella, verbose=False)
    assert tried > 0 and failures == 0


def test_stubs_match_the_compiled_module():
    stub = Path(inspect.getfile(tessella)).with_name("_tessella.pyi")
    tree = ast.parse(stub.read_text())
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    # The private helpers the package's own modules call are stubbed too (for mypy).
    compiled = {name for name, obj in vars(_tessella).items() if callable(obj) and not name.startswith("__")}
    assert stubbed == compiled
    assert Path(inspect.getfile(tessella)).with_name("py.typed").exists()


def test_every_public_function_is_documented():
    for name in tessella.__all__:
        obj = getattr(tessella, name)
        if callable(obj):
            assert obj.__doc__ and len(obj.__doc__) > 40, name
