"""The middlewares (rmw implementations) a robot may run on, and what each makes of QoS.

The QoS compatibility rules (``qos.profile_compatibility``) are rmw_dds_common's request/offered
rules, which every DDS middleware enforces. What differs between middlewares, and is data here:

* whether the middleware refuses a match at all (rmw_zenoh_cpp connects every publisher and
  subscription whatever their QoS: its ``rmw_qos_profile_check_compatible`` always answers
  "compatible" and its incompatible-QoS events never fire);
* what a policy left at ``SYSTEM_DEFAULT`` becomes when an endpoint is created (a DDS
  middleware leaves it to the DDS vendor's defaults, or maps it itself): known for Fast DDS
  and Cyclone DDS, where rmw_dds_common can only warn ("could be either").

docs/drift-rules.md ("QoS per middleware") has the table with the sources; each row has a unit
test (tests/unit/test_middlewares.py) and the Fast DDS row a witness on the real middleware
(tests/middleware/test_witnesses.py).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from ..errors import ContractError

#: the environment variable that selects the middleware of a ROS 2 process
VARIABLE = "RMW_IMPLEMENTATION"


@dataclass(frozen=True)
class Middleware:
    """One rmw implementation, as the compatibility rules see it."""

    name: str
    title: str
    #: False: it connects every publisher and subscription whatever their QoS
    refuses: bool = True
    #: what SYSTEM_DEFAULT becomes on a publisher (a DataWriter) and on a subscription (a
    #: DataReader), per policy; a policy not listed keeps rmw_dds_common's "could be either"
    writer_defaults: Mapping[str, str] = field(default_factory=dict)
    reader_defaults: Mapping[str, str] = field(default_factory=dict)


_FAST_DDS_WRITER = {"reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL", "liveliness": "AUTOMATIC"}
_FAST_DDS_READER = {"reliability": "BEST_EFFORT", "durability": "VOLATILE", "liveliness": "AUTOMATIC"}
_CYCLONE = {"reliability": "RELIABLE", "durability": "VOLATILE", "liveliness": "AUTOMATIC"}

#: every middleware the rules know, by its RMW_IMPLEMENTATION name
KNOWN: dict[str, Middleware] = {m.name: m for m in (
    Middleware("rmw_fastrtps_cpp", "Fast DDS", writer_defaults=_FAST_DDS_WRITER, reader_defaults=_FAST_DDS_READER),
    Middleware("rmw_fastrtps_dynamic_cpp", "Fast DDS (dynamic type support)", writer_defaults=_FAST_DDS_WRITER,
               reader_defaults=_FAST_DDS_READER),
    Middleware("rmw_cyclonedds_cpp", "Cyclone DDS", writer_defaults=_CYCLONE, reader_defaults=_CYCLONE),
    Middleware("rmw_connextdds", "RTI Connext DDS"),
    Middleware("rmw_zenoh_cpp", "Zenoh", refuses=False),
)}


def known_text() -> str:
    return ", ".join(KNOWN)


def get(name: str | None) -> Middleware | None:
    """The middleware called ``name`` (None: not said, DDS rules). Raises ValueError naming the
    known ones for a name the rules do not know."""
    if name is None:
        return None
    try:
        return KNOWN[name.strip()]
    except KeyError:
        raise ValueError(f"unknown middleware {name!r}: the QoS rules know {known_text()}") from None


def of_environment(env: Mapping[str, object] | None) -> str | None:
    """The middleware an environment selects (``RMW_IMPLEMENTATION``), None when it does not."""
    value = (env or {}).get(VARIABLE)
    return str(value).strip() if isinstance(value, str) and value.strip() else None


def choose(environments: Sequence[tuple[str, Mapping[str, object]]], option: str | None, *, shown: str) -> str | None:
    """The middleware of a system that does not say it with ``rmw:``: RMW_IMPLEMENTATION in its
    launch environment (``environments``: where, environment), else ``option`` (``--rmw``),
    else None. Raises ContractError (``shown``: the system contract) for a name the rules do not
    know, or several names."""
    found: dict[str, str] = {}
    for where, env in environments:
        value = of_environment(env)
        if value is not None:
            found.setdefault(value, where)
    if len(found) > 1:
        named = ", ".join(f"{name} ({where})" for name, where in found.items())
        raise ContractError(shown, None, f"the launch environment sets {VARIABLE} to several middlewares ({named}): "
                            f"say which one the system runs on with `rmw:` ({known_text()})")
    if found:
        ((name, where),) = found.items()
        if name not in KNOWN:
            raise ContractError(shown, None, f"{VARIABLE}={name} ({where}) is a middleware the QoS rules do not know "
                                f"({known_text()}): say which rules apply with `rmw:` in the system contract")
        return name
    return option
