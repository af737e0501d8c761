"""Section forms of a ``.gen`` file where the column-at-a-time reading once went its own way.

Each test reads a small file with both of supcoord's readings (the default one, a column
at a time where it can, and the token-by-token one) and compares them with libFAUDES's own
reading (``faudes.Generator`` / ``faudes.System``) or with the line the text itself puts
the refused token on.  Written for the surviving mutants of the ``.gen`` reader
(``benchmarks/mutation_run.py gen-reader``): a refused state index introduced by a
transition (named at line 1, or an ``OverflowError`` past 64 bits, before the fix), a bare
number in a state set that is a quoted state's name, a ``<Preemptible>`` flag before
``<Controllable>``, and the refused value of a file without ``<TransRel>``.
"""

from __future__ import annotations

import faudes
import pytest

from supcoord.des.io.gen_file import read_gen
from supcoord.des.io.gen_parser import parse_text_by_token
from supcoord.errors import FormatError


def _readings(path, text):
    """Both readings, each giving a :class:`~supcoord.des.generator.Generator`."""
    return (lambda: read_gen(path), lambda: parse_text_by_token(text, str(path)).to_generator())


def _file(states: str, trans: str, init: str = "1", marked: str = "", alphabet: str = "a", lead: str = "") -> str:
    return (f'{lead}<Generator> "g"\n<Alphabet> {alphabet} </Alphabet>\n<States> {states} </States>\n'
            f"<TransRel>\n{trans}\n</TransRel>\n<InitStates> {init} </InitStates>\n"
            f"<MarkedStates> {marked} </MarkedStates>\n</Generator>\n")


@pytest.mark.parametrize("lead", ["", "\n\n"])
@pytest.mark.parametrize("bad", ["0", "99999999999999999999"])
@pytest.mark.parametrize("before", [0, 2])
def test_a_refused_state_index_in_a_transition_names_its_line(tmp_path, lead, bad, before):
    trans = "\n".join([f"{k} a {k + 1}" for k in range(1, before + 1)] + [f"2 b {bad}"])
    text = _file("1 2 3", trans, alphabet="a b", lead=lead)
    path = tmp_path / "bad.gen"
    path.write_text(text)
    if bad == "0":  # libFAUDES refuses it too (past 64 bits it reads some other index; supcoord refuses)
        with pytest.raises(Exception):
            faudes.Generator(str(path))
    line = text[:text.index(f"2 b {bad}")].count("\n") + 1
    for read in _readings(path, text):
        with pytest.raises(FormatError) as info:
            read()
        assert str(info.value) == (f"{path}: line {line}: state index {bad} is not a positive integer "
                                   "(libFAUDES reserves 0 for 'no state')")
        assert info.value.value == int(bad)


@pytest.mark.parametrize("label", ["InitStates", "MarkedStates"])
def test_a_bare_number_in_a_state_set_is_an_index_not_a_quoted_name(tmp_path, label):
    """State 1 is named "5": a bare 5 in a state set is index 5 (not a state: refused), a
    quoted "5" is the state named so (read as libFAUDES reads it)."""
    for token, refused in (("5", True), ('"5"', False)):
        sets = {"init": "1", "marked": ""} | ({"init": token} if label == "InitStates" else {"marked": token})
        text = _file('"5" "x"', "", **sets)
        path = tmp_path / "g.gen"
        path.write_text(text)
        if refused:
            with pytest.raises(Exception):
                faudes.Generator(str(path))
            line = text[:text.index(f"<{label}>")].count("\n") + 1
            for read in _readings(path, text):
                with pytest.raises(FormatError, match=f"line {line}: state '5' is not in the state set"):
                    read()
            continue
        lists = faudes.Generator(str(path)).ToLists()
        want = {str(q) for q in (lists[-2] if label == "InitStates" else lists[-1])}
        assert want == {"5"}
        for read in _readings(path, text):
            g = read()
            got = {g.state_names[g.init]} if label == "InitStates" else {g.state_names[q] for q in g.marked}
            assert got == want


@pytest.mark.parametrize("alphabet", [
    '<Event name="a"> <Preemptible/> <Controllable/> </Event> <Event name="b"/>',
    "a <Preemptible/> <Controllable/> b",
    '<Event name="a"> <Preemptible value="1"/> <Forcible/> <Controllable value="1"/> </Event> b',
])
def test_a_preemptible_flag_before_controllable_keeps_the_event_controllable(tmp_path, alphabet):
    text = _file("1 2", "1 a 2\n1 b 1", alphabet=alphabet)
    path = tmp_path / "flags.gen"
    path.write_text(text)
    want = {str(e) for e in faudes.System(str(path)).ToLists()[2]}
    assert want == {"a"}
    for read in _readings(path, text):
        assert read().controllable == want


def test_a_native_file_without_transrel_is_refused_naming_the_section(tmp_path):
    text = '<Generator> "g"\n<Alphabet> a </Alphabet>\n<States> 1 2 </States>\n</Generator>\n'
    path = tmp_path / "short.gen"
    path.write_text(text)
    for read in _readings(path, text):
        with pytest.raises(FormatError) as info:
            read()
        assert "missing <TransRel> section" in str(info.value)
        assert info.value.value == "TransRel"
