"""Every language's table is one entry per name, and a MAX command's behaviour is bound on
its table entry once: mistakes are errors at import, not surprises at run time."""

import pytest

from maxk.commands.max.interpreter import Interpreter  # (imports bind every behaviour)
from maxk.commands.max.table import COMMANDS, Timing, bind
from maxk.commands.tables import TableError, unique_table


def test_a_name_listed_twice_is_refused():
    with pytest.raises(TableError, match="'VL' is listed twice"):
        unique_table(["VL", "AC", "VL"], str.upper, "MAX command table")
    assert list(unique_table(["VL", "AC"], str.upper)) == ["VL", "AC"]


def test_every_max_entry_has_its_behaviour_on_it():
    assert Interpreter is not None
    for mnemonic, spec in COMMANDS.items():
        if spec.timing is Timing.MODE or spec.start.value.startswith("linear"):
            assert spec.handler is None, mnemonic
        else:
            assert callable(spec.handler), mnemonic


def test_binding_twice_or_to_the_wrong_entry_is_refused():
    with pytest.raises(TableError, match="WY: bound twice"):
        bind(Timing.IMMEDIATE, {"WY": lambda ctx: "again"})
    with pytest.raises(TableError, match="VL: bound as immediate, listed as queued"):
        bind(Timing.IMMEDIATE, {"VL": lambda ctx: None})
    with pytest.raises(TableError, match="ZZ: a behaviour for a mnemonic not in the table"):
        bind(Timing.IMMEDIATE, {"ZZ": lambda ctx: None})
