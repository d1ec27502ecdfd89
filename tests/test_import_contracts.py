"""The public-namespaces contract (tests/import_contracts.py) on small import graphs.

``make test`` runs the contract on rubdiag itself (``lint-imports``); these tests check that it
catches what it is for: another package's private module imported directly, and an allowance
that no import uses any more.
"""

import grimp
import pytest
from import_contracts import PublicNamespacesContract, private_package


def _graph(*imports):
    graph = grimp.ImportGraph()
    for importer, imported in imports:
        for module in (importer, imported):
            graph.add_module(module)
        graph.add_import(importer=importer, imported=imported, line_number=3,
                         line_contents=f"from {imported} import x")
    return graph


def _check(graph, allowed=()):
    contract = PublicNamespacesContract(
        name="public namespaces", session_options={"root_packages": ["pkg"]},
        contract_options={"container": "pkg", "internal_interfaces": list(allowed)})
    return contract.check(graph, verbose=False)


@pytest.mark.parametrize(("module", "package"), [
    ("pkg.signal._table", "pkg.signal"),
    ("pkg.signal._lines._inner", "pkg.signal"),
    ("pkg.signal.public._detail", "pkg.signal"),
    ("pkg.signal", None),
    ("pkg.signal.public", None),
    ("pkg._kernels.newmark", None),      # top-level private: shared infrastructure
    ("pkg", None),
])
def test_a_module_is_private_to_the_package_it_sits_in(module, package):
    assert private_package(module, "pkg") == package


def test_importing_another_packages_private_module_breaks_the_contract():
    check = _check(_graph(("pkg.learn._train", "pkg.signal._table")))
    assert not check.kept
    assert check.metadata["breaches"] == [("pkg.learn._train", "pkg.signal._table", 3,
                                           "pkg.signal")]


def test_namespaces_own_privates_and_shared_infrastructure_keep_it():
    check = _check(_graph(("pkg.learn._train", "pkg.signal"),
                          ("pkg.learn._train", "pkg.learn._columns"),
                          ("pkg.learn", "pkg.learn._train"),
                          ("pkg.learn._train", "pkg._cache")))
    assert check.kept


def test_a_listed_internal_interface_is_allowed_and_only_for_its_importers():
    graph = _graph(("pkg.learn._train", "pkg.signal._table"),
                   ("pkg.runs._rows", "pkg.signal._table"))
    check = _check(graph, ["pkg.learn.* -> pkg.signal._table"])
    assert not check.kept
    assert [b[0] for b in check.metadata["breaches"]] == ["pkg.runs._rows"]


def test_an_allowance_no_import_uses_breaks_the_contract():
    check = _check(_graph(("pkg.learn._train", "pkg.signal")),
                   ["pkg.learn.* -> pkg.signal._table"])
    assert not check.kept
    assert check.metadata["unused"] == ["pkg.learn.* -> pkg.signal._table"]
