"""XML attribute values quoted as the standard library's ``xml.sax.saxutils.quoteattr`` does,
without importing ``xml.sax`` (which loads urllib, http.client and ssl: ~10 ms of start-up
for the VTK collections' two attributes)."""

from __future__ import annotations

__all__ = ["quote_attribute"]

#: characters escaped in an attribute value, ampersand first (as ``quoteattr``)
_ESCAPES = (("&", "&amp;"), (">", "&gt;"), ("<", "&lt;"), ("\n", "&#10;"), ("\r", "&#13;"),
            ("\t", "&#9;"))  # fmt: skip


def quote_attribute(value: str) -> str:
    """``value`` escaped and quoted as an XML attribute value (the same text as
    ``quoteattr``: double quotes, or single quotes when the value holds a double quote)."""
    for char, entity in _ESCAPES:
        value = value.replace(char, entity)
    if '"' not in value:
        return f'"{value}"'
    if "'" not in value:
        return f"'{value}'"
    return '"' + value.replace('"', "&quot;") + '"'
