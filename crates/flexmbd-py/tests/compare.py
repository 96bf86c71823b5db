"""Compare two JSON-like documents to round-off."""

import math


def assert_same(a, b, path="", rtol=1e-9, atol=1e-12, skip=()):
    """Recursive equality of dicts, lists, strings and numbers (numbers to rtol/atol);
    keys named in `skip` are not compared."""
    if isinstance(a, dict):
        assert isinstance(b, dict), f"{path}: dict vs {type(b).__name__}"
        assert set(a) == set(b), f"{path}: keys differ: {sorted(set(a) ^ set(b))}"
        for k in a:
            if k not in skip:
                assert_same(a[k], b[k], f"{path}.{k}", rtol, atol, skip)
    elif isinstance(a, list):
        assert isinstance(b, list), f"{path}: list vs {type(b).__name__}"
        assert len(a) == len(b), f"{path}: lengths {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{i}]", rtol, atol, skip)
    elif isinstance(a, bool) or a is None or isinstance(a, str):
        assert a == b, f"{path}: {a!r} != {b!r}"
    elif isinstance(a, (int, float)):
        assert isinstance(b, (int, float)) and not isinstance(b, bool), f"{path}: {a!r} vs {b!r}"
        if math.isnan(a) or math.isnan(b):
            assert math.isnan(a) and math.isnan(b), f"{path}: {a} != {b}"
        else:
            assert abs(a - b) <= atol + rtol * max(abs(a), abs(b)), f"{path}: {a!r} != {b!r}"
    else:
        raise AssertionError(f"{path}: unexpected type {type(a).__name__}")
