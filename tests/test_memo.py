"""morphkit.memo.Memo: made once, least recently used dropped first, counted."""

import pytest

from morphkit.errors import ValidationError
from morphkit.memo import Memo
from morphkit.validate import as_flag


def test_value_is_made_once_per_key():
    calls = []
    m = Memo()
    assert m.get("a", lambda: calls.append(1) or 7) == 7
    assert m.get("a", lambda: calls.append(1) or 8) == 7
    assert calls == [1] and (m.hits, m.misses) == (1, 1)


def test_least_recently_used_is_evicted_and_reported():
    dropped = []
    m = Memo(maxsize=2, on_evict=dropped.append)
    m.get(1, lambda: "one")
    m.get(2, lambda: "two")
    m.get(1, lambda: "x")        # 1 is now the most recent
    m.get(3, lambda: "three")    # so 2 goes
    assert dropped == ["two"] and 1 in m and 2 not in m and len(m) == 2
    m.clear()
    assert len(m) == 0 and (m.hits, m.misses) == (0, 0) and dropped == ["two"]


@pytest.mark.parametrize("bad", [0, -1, 2.5, True, "3"])
def test_bad_maxsize_is_refused(bad):
    with pytest.raises(ValidationError, match="maxsize: expected an integer >= 1"):
        Memo(maxsize=bad)


@pytest.mark.parametrize("bad", [0, 1, "yes", None, 1.0])
def test_as_flag_refuses_non_bools(bad):
    with pytest.raises(ValidationError, match="flag: expected a bool"):
        as_flag(bad, "flag")


def test_as_flag_accepts_numpy_bools():
    import numpy as np
    assert as_flag(np.bool_(True), "f") is True and as_flag(False, "f") is False
