"""A refused ``.gen`` state set names the offending token in the error's ``value``.

Library callers get a :class:`~supcoord.errors.FormatError` whose ``value`` is the token
the reader stopped at (the CLI and programs built on the library pass it on), besides the
one-line message with file and line.  Both readings are checked: the default one (a
column at a time where it can) and the token-by-token one (``parse_text_by_token``).
"""

from __future__ import annotations

import pytest

from supcoord.des.io.gen_file import read_gen
from supcoord.des.io.gen_parser import parse_text_by_token
from supcoord.errors import FormatError

HEAD = ('<Generator> "g"\n<Alphabet> a </Alphabet>\n<States> idle#1 busy#2 </States>\n'
        "<TransRel>\n1 a 2\n</TransRel>\n")


@pytest.mark.parametrize("label", ["InitStates", "MarkedStates"])
def test_a_state_set_without_its_end_tag_names_the_section(tmp_path, label):
    text = HEAD + ("<InitStates> 1 </InitStates>\n" if label == "MarkedStates" else "") + f"<{label}> 1 2\n"
    path = tmp_path / "open.gen"
    path.write_text(text)
    for read in (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path))):
        with pytest.raises(FormatError) as info:
            read()
        assert f"missing </{label}>" in str(info.value)
        assert info.value.value == label


@pytest.mark.parametrize("label", ["InitStates", "MarkedStates"])
@pytest.mark.parametrize("token", ["idle#1", "busy#2", "other#7"])
def test_an_index_suffix_in_a_state_set_is_the_refused_value(tmp_path, label, token):
    sets = {"InitStates": "1", "MarkedStates": ""}
    sets[label] = token
    text = HEAD + "".join(f"<{k}> {v} </{k}>\n" for k, v in sets.items()) + "</Generator>\n"
    path = tmp_path / "suffix.gen"
    path.write_text(text)
    for read in (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path))):
        with pytest.raises(FormatError) as info:
            read()
        assert f"index suffix not allowed in <{label}>" in str(info.value)
        assert info.value.value == token
