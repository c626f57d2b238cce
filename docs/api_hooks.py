"""mkdocs hook of the API reference (mkdocs.yml): the docstrings' Sphinx roles
(``:func:`name```, ``:class:`~name```) shown as the code they name, not as ":func:" before it
(mkdocstrings renders the role's text as it stands)."""

import re

ROLE = re.compile(r":(?:func|class|meth|data|mod|attr|exc|obj):(<code>)~?")


def on_page_content(html, **kwargs):
    return ROLE.sub(r"\1", html)
