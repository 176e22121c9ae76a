"""QoS vocabulary: contract form, profiles, expansion errors and the compatibility rules."""

import itertools

import pytest

from pytest_rmw_introspect.model import qos
from pytest_rmw_introspect.model.qos import Compatibility

S = 1_000_000_000
MS = 1_000_000


def raw(**overrides):
    """A raw capture QoS (design.md section 1): every field present."""
    base = {
        "history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
        "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0,
        "liveliness_lease_duration_ns": 0, "avoid_ros_namespace_conventions": False,
    }
    base.update(overrides)
    return base


# --------------------------------------------------------------------------- from_capture


@pytest.mark.parametrize(
    ("raw_qos", "contract"),
    [
        pytest.param(raw(), {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                             "durability": "VOLATILE"}, id="default"),
        pytest.param(raw(history="KEEP_ALL", depth=7),
                     {"history": "KEEP_ALL", "reliability": "RELIABLE", "durability": "VOLATILE"},
                     id="keep_all-drops-depth"),
        pytest.param(raw(history="SYSTEM_DEFAULT", depth=0, reliability="SYSTEM_DEFAULT",
                         durability="SYSTEM_DEFAULT"),
                     {"history": "SYSTEM_DEFAULT", "reliability": "SYSTEM_DEFAULT",
                      "durability": "SYSTEM_DEFAULT"}, id="system-default"),
        pytest.param(raw(deadline_ns=-1, lifespan_ns=-1, liveliness_lease_duration_ns=-1),
                     {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                      "durability": "VOLATILE"}, id="infinite-durations-omitted"),
        pytest.param(raw(deadline_ns=100 * MS, lifespan_ns=10 * S,
                         liveliness_lease_duration_ns=2 * S, liveliness="MANUAL_BY_TOPIC",
                         avoid_ros_namespace_conventions=True),
                     {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                      "durability": "VOLATILE", "liveliness": "MANUAL_BY_TOPIC",
                      "deadline_ns": 100 * MS, "lifespan_ns": 10 * S,
                      "liveliness_lease_duration_ns": 2 * S,
                      "avoid_ros_namespace_conventions": True}, id="everything-set"),
        pytest.param(raw(liveliness="AUTOMATIC"),
                     {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                      "durability": "VOLATILE", "liveliness": "AUTOMATIC"}, id="automatic-kept"),
        pytest.param(raw(deadline_ns=qos.DURATION_BEST_AVAILABLE),
                     {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE",
                      "durability": "VOLATILE", "deadline_ns": qos.DURATION_BEST_AVAILABLE},
                     id="best-available-deadline-kept"),
    ],
)
def test_from_capture(raw_qos, contract):
    result = qos.from_capture(raw_qos)
    assert result == contract
    assert list(result) == list(contract)  # key order is part of the contract form


def test_from_capture_maps_raw_infinite_constant_to_omitted():
    assert "deadline_ns" not in qos.from_capture(raw(deadline_ns=9_223_372_036_854_775_807))


def test_contract_form_round_trips_through_expand():
    original = raw(history="KEEP_LAST", depth=3, liveliness="MANUAL_BY_TOPIC", deadline_ns=5 * MS)
    assert qos.expand(qos.from_capture(original)) == original


# --------------------------------------------------------------------------- profiles


PROFILE_TABLE = [
    ("default", "KEEP_LAST", 10, "RELIABLE", "VOLATILE", 0),
    ("system_default", "SYSTEM_DEFAULT", 0, "SYSTEM_DEFAULT", "SYSTEM_DEFAULT", 0),
    ("sensor_data", "KEEP_LAST", 5, "BEST_EFFORT", "VOLATILE", 0),
    ("services_default", "KEEP_LAST", 10, "RELIABLE", "VOLATILE", 0),
    ("parameters", "KEEP_LAST", 1000, "RELIABLE", "VOLATILE", 0),
    ("parameter_events", "KEEP_LAST", 1000, "RELIABLE", "VOLATILE", 0),
    ("rosout", "KEEP_LAST", 1000, "RELIABLE", "TRANSIENT_LOCAL", 10 * S),
    ("map", "KEEP_LAST", 1, "RELIABLE", "TRANSIENT_LOCAL", 0),
]


@pytest.mark.parametrize(("name", "history", "depth", "reliability", "durability", "lifespan"),
                         PROFILE_TABLE)
def test_profile_expansion(name, history, depth, reliability, durability, lifespan):
    assert qos.expand(name) == raw(history=history, depth=depth, reliability=reliability,
                                   durability=durability, lifespan_ns=lifespan)


def test_profile_table_covers_every_profile():
    assert [row[0] for row in PROFILE_TABLE] == list(qos.PROFILES)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        ("default", "default"),
        ("services_default", "default"),  # identical profiles: the first name wins
        ("parameter_events", "parameters"),
        ("sensor_data", "sensor_data"),
        ("system_default", "system_default"),
        ("rosout", "rosout"),
        ("map", "map"),
        ({"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE",
          "durability": "TRANSIENT_LOCAL"}, "map"),
        (raw(history="KEEP_LAST", depth=5, reliability="BEST_EFFORT"), "sensor_data"),
        (raw(deadline_ns=-1), "default"),  # infinite == unspecified in contracts
        ({"profile": "sensor_data", "depth": 5}, "sensor_data"),
        ({"profile": "sensor_data", "depth": 1}, None),
        ({"profile": "map", "avoid_ros_namespace_conventions": True}, None),
        ({"depth": 11}, None),
        ({}, "default"),
    ],
)
def test_profile_name(value, expected):
    assert qos.profile_name(value) == expected


# --------------------------------------------------------------------------- expand


@pytest.mark.parametrize(
    ("value", "expected_overrides"),
    [
        ({}, {}),
        ({"depth": 1}, {"depth": 1}),
        ({"profile": "sensor_data", "depth": 1},
         {"depth": 1, "reliability": "BEST_EFFORT"}),
        ({"profile": "rosout", "durability": "volatile"},  # case-insensitive spellings
         {"depth": 1000, "lifespan_ns": 10 * S}),
        ({"history": "KEEP_ALL"}, {"history": "KEEP_ALL", "depth": 0}),
        ({"history": "SYSTEM_DEFAULT", "depth": 4}, {"history": "SYSTEM_DEFAULT", "depth": 0}),
        ({"lifespan_ns": -1, "deadline_ns": -1}, {}),
        ({"liveliness": "MANUAL_BY_TOPIC", "liveliness_lease_duration_ns": S},
         {"liveliness": "MANUAL_BY_TOPIC", "liveliness_lease_duration_ns": S}),
    ],
)
def test_expand_fills_every_field(value, expected_overrides):
    result = qos.expand(value)
    assert list(result) == list(qos.FIELDS)
    assert result == raw(**expected_overrides)


def test_expand_does_not_modify_its_input():
    value = {"profile": "sensor_data", "depth": 1}
    qos.expand(value)
    assert value == {"profile": "sensor_data", "depth": 1}
    qos.expand("sensor_data")["depth"] = 99
    assert qos.expand("sensor_data")["depth"] == 5


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("best_effort_please", "unknown QoS profile 'best_effort_please'"),
        ({"profile": "nope"}, "unknown QoS profile 'nope'"),
        ({"profile": 3}, "unknown QoS profile 3"),
        ({"reliabilty": "RELIABLE"}, "unknown QoS key 'reliabilty'"),
        ({"reliability": "SOMETIMES"}, "invalid QoS reliability 'SOMETIMES'"),
        ({"durability": "TRANSIENT"}, "invalid QoS durability 'TRANSIENT'"),
        ({"history": 1}, "invalid QoS history 1"),
        ({"liveliness": "MANUAL_BY_NODE"}, "invalid QoS liveliness 'MANUAL_BY_NODE'"),
        ({"depth": -1}, "invalid QoS depth -1"),
        ({"depth": "10"}, "invalid QoS depth '10'"),
        ({"depth": True}, "invalid QoS depth True"),
        ({"deadline_ns": 1.5}, "invalid QoS deadline_ns 1.5"),
        ({"lifespan_ns": -2}, "invalid QoS lifespan_ns -2"),
        ({"avoid_ros_namespace_conventions": "yes"},
         "invalid QoS avoid_ros_namespace_conventions 'yes'"),
        (5, "invalid QoS 5"),
        (None, "invalid QoS None"),
        (["RELIABLE"], "invalid QoS ['RELIABLE']"),
    ],
)
def test_expand_rejects_bad_input_naming_it(value, message):
    with pytest.raises(ValueError) as excinfo:
        qos.expand(value)
    assert str(excinfo.value).startswith(message)


def test_expand_error_lists_the_valid_choices():
    with pytest.raises(ValueError, match="expected one of SYSTEM_DEFAULT, RELIABLE, BEST_EFFORT"):
        qos.expand({"reliability": "bogus"})
    with pytest.raises(ValueError, match="default, system_default, sensor_data"):
        qos.expand("bogus")


@pytest.mark.parametrize(
    ("ns", "text"),
    [(0, "unset"), (-1, "infinite"), (10 * S, "10 s"), (250 * MS, "250 ms"), (5_000, "5 us"),
     (1_500_001, "1500001 ns"), (7, "7 ns"), (qos.DURATION_BEST_AVAILABLE, "best available")],
)
def test_format_duration(ns, text):
    assert qos.format_duration(ns) == text


# --------------------------------------------------------------------------- compatibility


def pair(pub=None, sub=None):
    return raw(**(pub or {})), raw(**(sub or {}))


# Every ERROR rule of rmw_dds_common's qos_profile_check_compatible.
ERROR_ROWS = [
    ("reliability", {"reliability": "BEST_EFFORT"}, {"reliability": "RELIABLE"},
     "BEST_EFFORT publisher and RELIABLE subscription"),
    ("durability", {"durability": "VOLATILE"}, {"durability": "TRANSIENT_LOCAL"},
     "VOLATILE publisher and TRANSIENT_LOCAL subscription"),
    ("deadline-unset-pub", {}, {"deadline_ns": S}, "subscription requests a deadline but"),
    ("deadline-infinite-sub-vs-unset-pub", {}, {"deadline_ns": -1},
     "subscription requests a deadline but"),
    ("deadline-shorter-sub", {"deadline_ns": 2 * S}, {"deadline_ns": S},
     "subscription deadline (1 s) is shorter than the publisher's (2 s)"),
    ("deadline-infinite-pub", {"deadline_ns": -1}, {"deadline_ns": S},
     "subscription deadline (1 s) is shorter than the publisher's (infinite)"),
    ("liveliness", {"liveliness": "AUTOMATIC"}, {"liveliness": "MANUAL_BY_TOPIC"},
     "AUTOMATIC liveliness publisher and MANUAL_BY_TOPIC subscription"),
    ("lease-unset-pub", {"liveliness": "AUTOMATIC"},
     {"liveliness": "AUTOMATIC", "liveliness_lease_duration_ns": S},
     "subscription requests a liveliness lease duration but"),
    ("lease-shorter-sub", {"liveliness": "AUTOMATIC", "liveliness_lease_duration_ns": 3 * S},
     {"liveliness": "AUTOMATIC", "liveliness_lease_duration_ns": S},
     "subscription liveliness lease duration (1 s) is shorter than the publisher's (3 s)"),
]


@pytest.mark.parametrize(("case", "pub", "sub", "reason"), ERROR_ROWS,
                         ids=[row[0] for row in ERROR_ROWS])
def test_errors(case, pub, sub, reason):
    # liveliness AUTOMATIC on both sides unless the row says otherwise: no stray warning
    pub = {"liveliness": "AUTOMATIC", **pub}
    sub = {"liveliness": "AUTOMATIC", **sub}
    compatibility, text = qos.profile_compatibility(*pair(pub, sub))
    assert compatibility is Compatibility.ERROR
    assert text == f"ERROR: {reason}" or text.startswith(f"ERROR: {reason}")
    assert "WARNING" not in text


# Every WARNING case: (policy, offered, requested) where one side is SYSTEM_DEFAULT or UNKNOWN.
WARNING_ROWS = [
    (policy, offered, requested)
    for policy, weak, strong in [
        ("reliability", "BEST_EFFORT", "RELIABLE"),
        ("durability", "VOLATILE", "TRANSIENT_LOCAL"),
        ("liveliness", "AUTOMATIC", "MANUAL_BY_TOPIC"),
    ]
    for offered, requested in [
        ("SYSTEM_DEFAULT", "SYSTEM_DEFAULT"),
        ("SYSTEM_DEFAULT", "UNKNOWN"),
        ("UNKNOWN", "SYSTEM_DEFAULT"),
        ("UNKNOWN", "UNKNOWN"),
        ("SYSTEM_DEFAULT", strong),
        ("UNKNOWN", strong),
        (weak, "SYSTEM_DEFAULT"),
        (weak, "UNKNOWN"),
    ]
]

# The same policies where nothing can go wrong: OK.
OK_ROWS = [
    (policy, offered, requested)
    for policy, weak, strong in [
        ("reliability", "BEST_EFFORT", "RELIABLE"),
        ("durability", "VOLATILE", "TRANSIENT_LOCAL"),
        ("liveliness", "AUTOMATIC", "MANUAL_BY_TOPIC"),
    ]
    for offered, requested in [
        (strong, strong), (strong, weak), (weak, weak),
        ("SYSTEM_DEFAULT", weak), ("UNKNOWN", weak),  # a weak request is always met
        (strong, "SYSTEM_DEFAULT"), (strong, "UNKNOWN"),  # a strong offer meets anything
        ("BEST_AVAILABLE", strong), (weak, "BEST_AVAILABLE"),
        ("BEST_AVAILABLE", "SYSTEM_DEFAULT"), ("SYSTEM_DEFAULT", "BEST_AVAILABLE"),
    ]
]

NEUTRAL = {"reliability": "RELIABLE", "durability": "VOLATILE", "liveliness": "AUTOMATIC"}


@pytest.mark.parametrize(("policy", "offered", "requested"), WARNING_ROWS)
def test_warnings(policy, offered, requested):
    compatibility, text = qos.profile_compatibility(
        *pair({**NEUTRAL, policy: offered}, {**NEUTRAL, policy: requested}))
    assert compatibility is Compatibility.WARNING
    assert text.startswith("WARNING: ") and policy in text
    assert text.count("WARNING") == 1


@pytest.mark.parametrize(("policy", "offered", "requested"), OK_ROWS)
def test_ok(policy, offered, requested):
    assert qos.profile_compatibility(
        *pair({**NEUTRAL, policy: offered}, {**NEUTRAL, policy: requested})
    ) == (Compatibility.OK, "")


@pytest.mark.parametrize(
    ("pub", "sub"),
    [
        ({"deadline_ns": S}, {"deadline_ns": S}),
        ({"deadline_ns": S}, {"deadline_ns": 2 * S}),
        ({"deadline_ns": S}, {}),  # subscription without deadline accepts any
        ({"deadline_ns": S}, {"deadline_ns": -1}),
        ({"deadline_ns": -1}, {"deadline_ns": -1}),
        ({"deadline_ns": -1}, {}),
        ({"liveliness_lease_duration_ns": S}, {"liveliness_lease_duration_ns": 5 * S}),
        ({"liveliness_lease_duration_ns": S}, {}),
        # BEST_AVAILABLE durations are resolved at creation: never compared
        ({"deadline_ns": qos.DURATION_BEST_AVAILABLE}, {"deadline_ns": S}),
        ({}, {"deadline_ns": qos.DURATION_BEST_AVAILABLE}),
        ({}, {"liveliness_lease_duration_ns": qos.DURATION_BEST_AVAILABLE}),
        # history, depth and lifespan never matter
        ({"history": "KEEP_ALL", "depth": 0, "lifespan_ns": S},
         {"history": "KEEP_LAST", "depth": 1, "lifespan_ns": 5}),
    ],
)
def test_duration_and_ignored_fields_ok(pub, sub):
    pub = {"liveliness": "AUTOMATIC", **pub}
    sub = {"liveliness": "AUTOMATIC", **sub}
    assert qos.profile_compatibility(*pair(pub, sub)) == (Compatibility.OK, "")


def test_warnings_are_only_reported_without_errors():
    # reliability error plus a durability situation that alone would be a warning
    compatibility, text = qos.profile_compatibility(
        *pair({"reliability": "BEST_EFFORT", "durability": "SYSTEM_DEFAULT"},
              {"reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}))
    assert compatibility is Compatibility.ERROR
    assert "WARNING" not in text


def test_all_errors_are_reported_in_rule_order():
    _, text = qos.profile_compatibility(
        *pair({"reliability": "BEST_EFFORT", "liveliness": "AUTOMATIC"},
              {"durability": "TRANSIENT_LOCAL", "deadline_ns": S, "liveliness": "MANUAL_BY_TOPIC"}))
    assert [part.split(" ")[1] for part in text.split("; ")] == [
        "BEST_EFFORT", "VOLATILE", "subscription", "AUTOMATIC"]


def test_default_profiles_warn_about_system_default_liveliness():
    # rmw's own profiles leave liveliness at SYSTEM_DEFAULT: rmw answers WARNING, so do we
    assert qos.profile_compatibility("default", "default")[0] is Compatibility.WARNING


def test_profile_compatibility_accepts_contract_forms():
    assert qos.profile_compatibility("sensor_data", "default")[0] is Compatibility.ERROR
    assert qos.profile_compatibility({"profile": "map", "liveliness": "AUTOMATIC"},
                                {"profile": "map", "liveliness": "AUTOMATIC"}) == (
        Compatibility.OK, "")


# --------------------------------------------------------------------------- against rmw itself


def _rclpy_profile(rclpy_qos, explicit):
    from rclpy.duration import Duration, Infinite

    def duration(ns):
        return Infinite if ns == -1 else Duration(nanoseconds=ns)

    return rclpy_qos.QoSProfile(
        history=rclpy_qos.HistoryPolicy[explicit["history"]],
        depth=explicit["depth"],
        reliability=rclpy_qos.ReliabilityPolicy[explicit["reliability"]],
        durability=rclpy_qos.DurabilityPolicy[explicit["durability"]],
        liveliness=rclpy_qos.LivelinessPolicy[explicit["liveliness"]],
        deadline=duration(explicit["deadline_ns"]),
        lifespan=duration(explicit["lifespan_ns"]),
        liveliness_lease_duration=duration(explicit["liveliness_lease_duration_ns"]),
    )


def _assert_matches_rmw(cases):
    rclpy_qos = pytest.importorskip("rclpy.qos")
    mismatches = []
    for pub, sub in cases:
        expected = rclpy_qos.qos_check_compatible(
            _rclpy_profile(rclpy_qos, pub), _rclpy_profile(rclpy_qos, sub))[0]
        actual = qos.profile_compatibility(pub, sub)[0]
        if int(expected) != int(actual):
            mismatches.append((pub, sub, expected, actual))
    assert not mismatches, mismatches[:5]
    assert len(cases) > 0


def test_enum_policies_match_rmw_dds_common():
    """Oracle: rclpy's qos_check_compatible (rmw_dds_common) over every enum combination."""
    values = {field: [member.value for member in qos.ENUM_FIELDS[field]]
              for field in ("reliability", "durability", "liveliness")}
    profiles = [raw(reliability=r, durability=d, liveliness=lv)
                for r, d, lv in itertools.product(*values.values())]
    _assert_matches_rmw(list(itertools.product(profiles, profiles)))


def test_durations_match_rmw_dds_common():
    durations = [0, -1, S, 2 * S]
    profiles = [raw(liveliness="AUTOMATIC", deadline_ns=d, liveliness_lease_duration_ns=lease)
                for d, lease in itertools.product(durations, durations)]
    _assert_matches_rmw(list(itertools.product(profiles, profiles)))
