"""Resolve the docstrings' short references to where each object is documented.

asperity's packages re-export their public names (``asperity.statmodel.shear_curve`` is
defined in ``asperity.statmodel.shear``), and docstrings refer to them as users import them:
``:func:`statmodel.shear_curve```, ``:func:`asperity.bem.solve_contact```, or a bare
``:func:`read_surface``` inside ``asperity.topo``. The API reference documents each object once,
under the module that defines it, so those names have no target of their own. This extension
handles Sphinx's ``missing-reference`` event: it imports the name as written (prefixed with
``asperity.`` where it starts with a sub-package, or looked up in the current module and its
parent packages), takes the object's defining ``__module__.__qualname__`` and resolves the
reference there. Only names under ``asperity`` are imported; anything else stays unresolved.
"""

from __future__ import annotations

import functools
import importlib
import inspect
from typing import Any

SUBPACKAGES = ("topo", "bem", "statmodel", "pipelines", "errors", "plotting", "schema")


@functools.cache
def canonical_name(dotted: str) -> str | None:
    """``module.qualname`` of the object ``dotted`` names (None if it is not importable)."""
    if not dotted.startswith("asperity."):
        return None
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for name in parts[cut:]:
                obj = getattr(obj, name)
        except AttributeError:
            return None
        break
    else:
        return None
    if inspect.ismodule(obj):
        return obj.__name__
    module, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
    if isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname:
        return f"{module}.{qualname}"
    return None


def candidates(target: str, current_module: str | None) -> list[str]:
    """Full names ``target`` may stand for, most specific first."""
    target = target.lstrip("~.")
    names = []
    if target.split(".")[0] in SUBPACKAGES:
        names.append(f"asperity.{target}")
    elif target.startswith("asperity."):
        names.append(target)
    if current_module and current_module.startswith("asperity"):
        parts = current_module.split(".")
        names += [".".join([*parts[:cut], target]) for cut in range(len(parts), 0, -1)]
    return names


def resolve_alias(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """``missing-reference`` handler: the reference resolved at the canonical name, or None."""
    if node.get("refdomain") != "py":
        return None
    domain = env.get_domain("py")
    for name in candidates(node["reftarget"], node.get("py:module")):
        target = canonical_name(name)
        if target is None or target == node["reftarget"]:
            continue
        found = domain.resolve_xref(env, node["refdoc"], app.builder, "obj", target, node, contnode)
        if found is not None:
            return found
    return None


def setup(app: Any) -> dict[str, Any]:
    """Register the handler."""
    app.connect("missing-reference", resolve_alias)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
