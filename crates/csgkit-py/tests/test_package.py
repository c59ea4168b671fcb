"""The package as published: its docstring examples run, and its type stubs name exactly
the native module's functions, classes and parameters."""

import ast
import doctest
import inspect
from pathlib import Path

import pytest

import csgkit
import csgkit._csgkit as native

STUB = Path(native.__file__).with_name("_csgkit.pyi")


@pytest.mark.parametrize("module", ["csgkit", "csgkit._csgkit", "csgkit.trimesh"])
def test_docstring_examples_run(module):
    if module == "csgkit.trimesh":
        pytest.importorskip("trimesh")
    imported = __import__(module, fromlist=["_"])
    finder = doctest.DocTestFinder()
    tests = [t for t in finder.find(imported, module) if t.examples]
    # The finder skips objects defined in another module; a native module's functions and
    # classes name it as theirs, but look at each one explicitly all the same.
    if module == "csgkit._csgkit":
        seen = {t.name for t in tests}
        for name, obj in vars(imported).items():
            if callable(obj) and obj.__doc__ and f"{module}.{name}" not in seen:
                tests += [t for t in finder.find(obj, f"{module}.{name}") if t.examples]
    assert tests, f"{module} has no examples"
    runner = doctest.DocTestRunner()
    for test in tests:
        runner.run(test)
    assert runner.failures == 0, runner.summarize()


def stub_definitions():
    """The stub's functions, as {name: arguments}: `def`s, and names annotated with a
    Protocol class, whose `__call__` gives the arguments; and its public classes."""
    tree = ast.parse(STUB.read_text())
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    functions = {n.name: n.args for n in tree.body if isinstance(n, ast.FunctionDef)}
    for node in tree.body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.annotation, ast.Name):
            protocol = classes.get(node.annotation.id)
            if protocol is not None:
                call = next(n for n in protocol.body if isinstance(n, ast.FunctionDef) and n.name == "__call__")
                functions[node.target.id] = call.args
    public = {name: c for name, c in classes.items() if not name.startswith("_")}
    return functions, public


def test_the_stub_names_every_function_and_its_parameters():
    functions, _ = stub_definitions()
    runtime = {n for n, o in vars(native).items() if inspect.isbuiltin(o) or inspect.isfunction(o)}
    assert set(functions) == runtime
    for name, args in functions.items():
        stubbed = [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs if a.arg != "self"]
        if args.vararg:
            stubbed.insert(0, args.vararg.arg)
        actual = list(inspect.signature(getattr(native, name)).parameters)
        assert stubbed == actual, name


def test_the_stub_names_every_property_of_mesh():
    _, classes = stub_definitions()
    assert set(classes) == {"Mesh"}
    stubbed = {n.name for n in classes["Mesh"].body
               if isinstance(n, ast.FunctionDef) and not n.name.startswith("__")}
    actual = {n for n, o in vars(csgkit.Mesh).items() if inspect.isgetsetdescriptor(o)}
    assert stubbed == actual
    assert (Path(native.__file__).parent / "py.typed").exists()
    assert set(csgkit.__all__) >= set(functions_and_classes()) | {"CsgkitError", "InputError"}


def functions_and_classes():
    """The public names of the stub (pickling's `_mesh_from_state` is private)."""
    functions, classes = stub_definitions()
    return {name for name in set(functions) | set(classes) if not name.startswith("_")}
