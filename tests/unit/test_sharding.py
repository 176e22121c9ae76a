"""``--shard I/N``: each CI job's share of the contracts."""

from __future__ import annotations

import random

import pytest

from pytest_rmw_introspect.check import sharding
from pytest_rmw_introspect.errors import UsageError

CONTRACTS = [f"contracts/node_{i:02d}.interfaces.yaml" for i in range(11)]


@pytest.mark.parametrize("count", [1, 2, 3, 4, 11, 15])
def test_the_shards_together_take_every_contract_exactly_once_in_near_equal_shares(count):
    shares = [sharding.Shard(i, count).select(CONTRACTS, str) for i in range(1, count + 1)]
    taken = [c for share in shares for c in share]
    assert sorted(taken) == sorted(CONTRACTS)  # the union is the unsharded run, nothing twice
    sizes = [len(share) for share in shares]
    assert max(sizes) - min(sizes) <= 1


def test_a_share_does_not_depend_on_the_order_the_contracts_come_in():
    shuffled = list(CONTRACTS)
    random.Random(4).shuffle(shuffled)
    for index in (1, 2, 3):
        shard = sharding.Shard(index, 3)
        assert sorted(shard.select(shuffled, str)) == sorted(shard.select(CONTRACTS, str))
    assert sharding.Shard(1, 3).select(shuffled, str) == [c for c in shuffled if c in sharding.Shard(1, 3).select(CONTRACTS, str)]


def test_the_same_key_stays_in_one_shard():
    things = ["a", "a", "b", "c"]
    assert sharding.Shard(1, 3).select(things, str) == ["a", "a"]


@pytest.mark.parametrize(("text", "expected"), [("1/1", (1, 1)), ("2/4", (2, 4)), (" 3 / 3 ", (3, 3))])
def test_parse(text, expected):
    shard = sharding.parse(text)
    assert (shard.index, shard.count) == expected and str(shard) == f"{expected[0]}/{expected[1]}"


@pytest.mark.parametrize(("text", "message"), [
    ("2", "is not of the form I/N"), ("a/b", "is not of the form I/N"), ("0/2", "I must be between 1 and N"),
    ("3/2", "I must be between 1 and N"), ("1/0", "I must be between 1 and N"),
])
def test_bad_shards_say_what_to_write(text, message):
    with pytest.raises(UsageError, match=message):
        sharding.parse(text)
