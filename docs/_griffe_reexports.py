"""Griffe extension: a package's re-exports are its public names.

Every `__init__.py` of teflon_jax and identification re-exports its public names from private
modules with the redundant alias `from ._module import name as name` (PEP 484's explicit
re-export); griffe does not count those as public by itself, so mkdocstrings would list none.
"""

import griffe


class PublicReexports(griffe.Extension):
    """In a public package (`__init__.py`), every alias without a leading underscore is public."""

    def on_module(self, *, mod: griffe.Module, **kwargs) -> None:
        if getattr(mod.filepath, "name", "") != "__init__.py" or any(part.startswith("_") for part in mod.path.split(".")):
            return
        for name, member in mod.members.items():
            if member.is_alias and not name.startswith("_"):
                member.public = True
