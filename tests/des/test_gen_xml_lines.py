"""A refused ``.gen`` file of the XML layout names the lines of the offending transitions.

Two transitions of one state on one event (supcoord's generators are deterministic) are
refused naming the line of each ``<Transition>`` element, as the native layout names the lines
of ``<TransRel>``; both readings are checked, the default one and the token-by-token one.
"""

from __future__ import annotations

import pytest

from supcoord.des.io.gen_file import read_gen
from supcoord.des.io.gen_parser import parse_text_by_token
from supcoord.errors import NondeterminismError


def _xml(blank_lines: int, between: int) -> str:
    head = "\n" * blank_lines + ('<Generator name="g">\n<Alphabet>\n<Event name="a"/>\n<Event name="b"/>\n</Alphabet>\n'
                                 '<StateSet>\n<State id="1"><Initial/></State>\n<State id="2"/>\n<State id="3"/>\n'
                                 '</StateSet>\n<TransitionRelation>\n')
    middle = "".join(f'<Transition x1="2" event="{e}" x2="3"/>\n' for e in "ab"[:between])
    return (head + '<Transition x1="1" event="a" x2="2"/>\n' + middle + '<Transition x1="1" event="a" x2="3"/>\n'
            '</TransitionRelation>\n</Generator>\n')


@pytest.mark.parametrize("blank_lines, between", [(0, 0), (3, 0), (0, 1), (5, 2)])
def test_two_transitions_on_one_event_name_their_lines(tmp_path, blank_lines, between):
    text = _xml(blank_lines, between)
    lines = text.splitlines()
    first = lines.index('<Transition x1="1" event="a" x2="2"/>') + 1
    second = lines.index('<Transition x1="1" event="a" x2="3"/>') + 1
    path = tmp_path / "g.gen"
    path.write_text(text)
    for read in (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path))):
        with pytest.raises(NondeterminismError) as info:
            read()
        message = str(info.value)
        assert f"line {second}: state 1 has two transitions on 'a', to 2 (line {first}) and to 3" in message, message
