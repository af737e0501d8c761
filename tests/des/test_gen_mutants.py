"""The lines a refused nondeterministic ``.gen`` file names, at every position of the clash.

Two transitions of one state on one event are refused with the line of each; the line of
the ``k``-th transition is found again by reading the transition relation up to it (attributes
in between skipped).  The expected lines come from the text itself (where each transition
was written), for both layouts (``<TransRel>`` triples and XML ``<Transition>`` elements),
both readings (the default one and the token-by-token one), transitions several to a line
and every attribute form libFAUDES skips after a transition."""

from __future__ import annotations

import pytest

from supcoord.des import flat_ops
from supcoord.des.flat import from_generator
from supcoord.des.generator import Event, Generator
from supcoord.des.io.gen_file import read_gen
from supcoord.des.io.gen_parser import parse_text_by_token
from supcoord.des.io.gen_write import write_gen_flat
from supcoord.errors import FormatError, NondeterminismError

# what may follow a transition of <TransRel> (libFAUDES's AttributeVoid skips it)
ATTRIBUTES = ["", " +Opt+", " 0x0f", " -3", ' <Foreign> 1 "x" </Foreign>']


def _native(before: int, between: int, attribute: str, per_line: int) -> tuple[str, int, int]:
    """A native-layout generator: ``before`` transitions, the first of the clash, ``between``
    more, the second; ``per_line`` transitions to a line.  The text and the clash's lines."""
    filler = [f"{2 + i} b {3 + i}" for i in range(before + between)]
    trans = filler[:before] + ["1 a 2"] + filler[before:] + ["1 a 3"]
    first_k, second_k = before, len(trans) - 1
    head = '<Generator> "g"\n<Alphabet> a b </Alphabet>\n'
    head += "<States> " + " ".join(str(i) for i in range(1, before + between + 4)) + " </States>\n<TransRel>\n"
    body, line_of = [], {}
    for k, t in enumerate(trans):
        if k % per_line == 0:
            body.append("")
        line_of[k] = head.count("\n") + len(body)
        body[-1] += t + (attribute if k % 2 == 0 else "") + " "
    text = head + "\n".join(body) + "\n</TransRel>\n<InitStates> 1 </InitStates>\n<MarkedStates> </MarkedStates>\n"
    return text + "</Generator>\n", line_of[first_k], line_of[second_k]


def _refused(tmp_path, text: str) -> list[str]:
    path = tmp_path / "nd.gen"
    path.write_text(text)
    messages = []
    for read in (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path))):
        with pytest.raises(NondeterminismError) as info:
            read()
        messages.append(str(info.value).removeprefix(f"{path}: "))
    return messages


@pytest.mark.parametrize("attribute", ATTRIBUTES)
@pytest.mark.parametrize("before,between,per_line", [(0, 0, 1), (2, 1, 1), (1, 3, 2), (3, 2, 3)])
def test_native_clash_names_the_lines_of_both_transitions(tmp_path, attribute, before, between, per_line):
    text, first, second = _native(before, between, attribute, per_line)
    want = f"line {second}: state 1 has two transitions on 'a', to 2 (line {first}) and to 3"
    assert _refused(tmp_path, text) == [want, want]


@pytest.mark.parametrize("before,between", [(0, 0), (2, 1), (1, 3)])
def test_xml_clash_names_the_lines_of_both_transitions(tmp_path, before, between):
    n = before + between + 3
    head = ['<Generator name="g">', "<Alphabet>", '<Event name="a"/>', '<Event name="b"/>', "</Alphabet>", "<StateSet>",
            '<State id="1"><Initial/></State>'] + [f'<State id="{i}"/>' for i in range(2, n + 1)]
    head += ["</StateSet>", "<TransitionRelation>"]
    filler = [f'<Transition x1="{2 + i}" event="b" x2="{3 + i}"/>' for i in range(before + between)]
    trans = filler[:before] + ['<Transition x1="1" event="a" x2="2"/>'] + filler[before:]
    trans += ['<Transition x1="1" event="a" x2="3"/>']
    lines = head + trans + ["</TransitionRelation>", "</Generator>"]
    first = len(head) + before + 1
    second = len(head) + len(trans)
    want = f"line {second}: state 1 has two transitions on 'a', to 2 (line {first}) and to 3"
    assert _refused(tmp_path, "\n".join(lines) + "\n") == [want, want]


def _xml(states: str, trans: str = "") -> str:
    return ('<Generator name="g">\n<Alphabet><Event name="a"/></Alphabet>\n'
            f"<StateSet>\n{states}\n</StateSet>\n<TransitionRelation>\n{trans}</TransitionRelation>\n</Generator>\n")


def _refusal(tmp_path, text: str) -> list[tuple[str, object]]:
    path = tmp_path / "bad.gen"
    path.write_text(text)
    out = []
    for read in (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path))):
        with pytest.raises(FormatError) as info:
            read()
        out.append((str(info.value).removeprefix(f"{path}: "), info.value.value))
    return out


@pytest.mark.parametrize("first,last", [(3, 2), (0, 2), (2, 0)])
def test_xml_consecutive_range_out_of_order_is_refused(tmp_path, first, last):
    text = _xml(f'<State id="1"/>\n<Consecutive from="{first}" to="{last}"/>')
    want = (f"line 5: invalid range of consecutive states {first}..{last}", (first, last))
    assert _refusal(tmp_path, text) == [want, want]


def test_xml_state_without_a_positive_id_is_refused_quoting_it(tmp_path):
    text = _xml('<State id="1"/>\n<State id="0"/>')
    messages = [m for m, _ in _refusal(tmp_path, text)]
    assert messages == ["line 5: <State> needs a positive integer id, got '0'"] * 2


def test_xml_transition_listed_twice_is_refused(tmp_path):
    twice = '<Transition x1="1" event="a" x2="2"/>\n'
    text = _xml('<State id="1"/>\n<State id="2"/>', twice + twice)
    want = "line 9: transition {'x1': '1', 'event': 'a', 'x2': '2'} appears twice"
    assert [m for m, _ in _refusal(tmp_path, text)] == [want, want]


def test_flat_writer_writes_latin_1_as_the_reader_reads(tmp_path):
    """A generator named with a Latin-1 letter: the file holds it as one Latin-1 byte (the
    encoding of the transition bytes) and reads back under the same name."""
    g = Generator(2, [Event("a", True)], [(0, "a", 1)], 0, [1], name="café")
    path = tmp_path / "g.gen"
    write_gen_flat(from_generator(g), path)
    assert 'name="café"'.encode("latin-1") in path.read_bytes()
    assert read_gen(path).name == "café"


def test_flat_writer_orders_large_generators_as_small_ones(tmp_path, monkeypatch):
    """Beyond the successor table's size the transitions are sorted without it: by source
    state, then event name (here ``b`` before ``c`` though ``c`` was declared first), the same
    file as through the table."""
    g = Generator(3, [Event("c", True), Event("b", False), Event("a", True)],
                  [(2, "a", 0), (0, "c", 1), (0, "b", 2), (1, "c", 2), (0, "a", 0)], 0, [2])
    small, large = tmp_path / "small.gen", tmp_path / "large.gen"
    write_gen_flat(from_generator(g), small, names_in_transitions=False)
    monkeypatch.setattr(flat_ops, "TABLE_CELLS", 0)
    write_gen_flat(from_generator(g), large, names_in_transitions=False)
    text = large.read_text(encoding="latin-1")
    rows = text.split("<TransRel>")[1].split("</TransRel>")[0].split()
    assert rows == "1 a 1 1 b 3 1 c 2 2 c 3 3 a 1".split()
    assert text == small.read_text(encoding="latin-1")


@pytest.mark.parametrize("states,trans,want", [
    ("<Foo/> 1 2", "1 a 2", "line 3: unexpected <Foo> in <States>"),
    ("1 2", "1 a <Foo/>", "line 5: incomplete transition before <Foo> in <TransRel>")])
def test_a_stray_element_is_refused_at_its_line(tmp_path, states, trans, want):
    text = (f'<Generator> "g"\n<Alphabet> a </Alphabet>\n<States> {states} </States>\n<TransRel>\n{trans}\n'
            "</TransRel>\n<InitStates> 1 </InitStates>\n<MarkedStates> </MarkedStates>\n</Generator>\n")
    assert [m for m, _ in _refusal(tmp_path, text)] == [want, want]
