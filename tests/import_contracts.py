"""An import-linter contract: packages meet through their public namespaces.

SciPy's layout: a package such as ``rubdiag.signal`` keeps its code in private modules
(``rubdiag.signal._table``) and exports its public names from ``rubdiag/signal/__init__.py``.
The contract holds every other module to that: it imports ``rubdiag.signal``, never
``rubdiag.signal._table``, unless the import matches one of ``internal_interfaces`` — the
few private modules that two packages share on purpose (a column separator, a cached rig
model), each listed with who may use it, so that a new coupling is a reviewed line in
``pyproject.toml``. An allowance that matches no import any more is an error too, so the
list only holds what is used.

A package's own modules import each other freely, and top-level private modules
(``rubdiag._kernels``, ``rubdiag._cache``) are shared infrastructure, as ``scipy._lib`` is.

``make test`` runs it with the other contracts (``lint-imports`` from the repository root,
which puts this folder on the path).
"""

from __future__ import annotations

from grimp import ImportGraph
from importlinter import Contract, ContractCheck, fields, output


def private_package(module: str, container: str) -> str | None:
    """The public package whose private module ``module`` is, or None.

    >>> private_package("rubdiag.signal._table", "rubdiag")
    'rubdiag.signal'
    >>> private_package("rubdiag.signal", "rubdiag") is None
    True
    >>> private_package("rubdiag._kernels.newmark", "rubdiag") is None
    True
    """
    parts = module.split(".")
    depth = len(container.split("."))
    if len(parts) <= depth + 1 or parts[depth].startswith("_"):
        return None
    if any(part.startswith("_") for part in parts[depth + 1:]):
        return ".".join(parts[:depth + 1])
    return None


class PublicNamespacesContract(Contract):
    """Modules outside a package import it through its namespace, not its private modules."""

    type_name = "public_namespaces"

    container = fields.StringField()
    internal_interfaces = fields.SetField(subfield=fields.ImportExpressionField(),
                                          required=False, default=set())

    def check(self, graph: ImportGraph, verbose: bool) -> ContractCheck:
        allowed = set()
        unused = []
        for expression in sorted(self.internal_interfaces, key=str):
            matches = graph.find_matching_direct_imports(import_expression=str(expression))
            if not matches:
                unused.append(str(expression))
            allowed.update((m["importer"], m["imported"]) for m in matches)

        breaches = []
        for importer in sorted(graph.modules):
            if not (importer == self.container or importer.startswith(self.container + ".")):
                continue
            for imported in sorted(graph.find_modules_directly_imported_by(importer)):
                package = private_package(imported, self.container)
                if (package is None or importer == package
                        or importer.startswith(package + ".")
                        or (importer, imported) in allowed):
                    continue
                line = graph.get_import_details(importer=importer, imported=imported)[0]
                breaches.append((importer, imported, line["line_number"], package))
        return ContractCheck(kept=not breaches and not unused,
                             metadata={"breaches": breaches, "unused": unused})

    def render_broken_contract(self, check: ContractCheck) -> None:
        for importer, imported, line, package in check.metadata["breaches"]:
            output.print_error(f"{importer} (line {line}) imports {imported}: "
                               f"import {package} instead, or list the import as an "
                               f"internal interface", bold=False)
        for expression in check.metadata["unused"]:
            output.print_error(f"internal interface {expression} matches no import: "
                               f"remove it from the contract", bold=False)
