"""quote_attribute writes the same attribute text as the standard library's quoteattr."""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

import pytest

from fretbem.views.markup import quote_attribute


@pytest.mark.parametrize(
    "value",
    ["A", "", "step 1", "a&b", "<x>", 'say "hi"', "it's", "both \"'", "&amp;", "tab\there",
     "line\nbreak\r", "vtk/A_upper.vtp", "ünïcode ±", "\"'&<>\n\r\t"],
)  # fmt: skip
def test_same_text_as_quoteattr(value: str) -> None:
    assert quote_attribute(value) == quoteattr(value)
