"""rosbag2 recordings, read for what they show of a system: the recorded topics with their type,
type hash (where recorded), the QoS profiles their publishers offered and how many messages each
holds (``rmw-introspect check --bag``).

What is read, and from where (rosbag2's own layout; docs/recordings.md):

* a **bag directory**: ``metadata.yaml`` (``rosbag2_bagfile_information``, versions 1 to 9: the
  offered QoS profiles a YAML string up to version 8, a list from version 9; the type hash from
  version 7) names the storage (``storage_identifier``: ``sqlite3`` or ``mcap``) and its files,
  each of which is opened and read too: a file that is missing, corrupt or truncated is an error,
  and the files' topics and message counts are the ones reported (the metadata's where a file is
  compressed as a whole);
* a **plain ``.mcap`` file** (rosbag2's MCAP storage, or any ROS 2 MCAP file): the channels (topic,
  ``message_encoding``), their schemas (the type name) and channel metadata
  (``offered_qos_profiles``, ``topic_type_hash``, as rosbag2_storage_mcap writes them), the message
  counts of the summary's statistics; read with the ``mcap`` library;
* a **plain ``.db3`` file** (rosbag2's sqlite3 storage): its ``topics`` table (``name``, ``type``,
  ``serialization_format``, ``offered_qos_profiles``, and ``type_description_hash`` where the schema
  has it) and the count of its ``messages`` per topic; read with the standard library's sqlite3.

QoS policies are read in both of rosbag2's spellings (integers of rmw's enums up to metadata
version 8, lower-case names from version 9) into the raw capture form of ``model.qos`` (durations
in nanoseconds, 0 unspecified, -1 infinite; the "infinite" values older middlewares wrote too).

Every problem is a :class:`errors.RecordingError` naming the path and what to do.
"""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcap.reader import make_reader

from ..errors import InputError, RecordingError
from . import untrusted
from .paths import shown as display

#: the storage identifiers this reader reads (``storage_identifier`` of ``metadata.yaml``)
STORAGES = ("sqlite3", "mcap")
METADATA_FILE = "metadata.yaml"

# rmw's enums, by their integer values (rosbag2 metadata up to version 8)
_HISTORY = {0: "SYSTEM_DEFAULT", 1: "KEEP_LAST", 2: "KEEP_ALL", 3: "UNKNOWN"}
_RELIABILITY = {0: "SYSTEM_DEFAULT", 1: "RELIABLE", 2: "BEST_EFFORT", 3: "UNKNOWN", 4: "BEST_AVAILABLE"}
_DURABILITY = {0: "SYSTEM_DEFAULT", 1: "TRANSIENT_LOCAL", 2: "VOLATILE", 3: "UNKNOWN", 4: "BEST_AVAILABLE"}
# 2 is the deprecated MANUAL_BY_NODE, which no middleware of Jazzy or later offers
_LIVELINESS = {0: "SYSTEM_DEFAULT", 1: "AUTOMATIC", 2: "UNKNOWN", 3: "MANUAL_BY_TOPIC", 4: "UNKNOWN", 5: "BEST_AVAILABLE"}
_ENUMS = {"history": _HISTORY, "reliability": _RELIABILITY, "durability": _DURABILITY, "liveliness": _LIVELINESS}
_DURATIONS = {"deadline": "deadline_ns", "lifespan": "lifespan_ns", "liveliness_lease_duration": "liveliness_lease_duration_ns"}
# "infinite" as RMW_DURATION_INFINITE and as Foxy's middlewares wrote it (rosbag2_storage's qos.cpp)
_INFINITE = {(9_223_372_036, 854_775_807), (0x7FFFFFFF, 0xFFFFFFFF), (0x7FFFFFFF, 0x7FFFFFFF)}
_SECOND = 1_000_000_000


@dataclass(frozen=True)
class RecordedTopic:
    """One topic of a recording: ``qos_profiles`` are the QoS its publishers offered when the
    recorder found them (raw capture form, one per publisher), ``type_hash`` None where the
    recording does not hold one, ``message_count`` None where it could not be counted."""

    name: str
    type: str
    serialization_format: str = "cdr"
    qos_profiles: tuple[Mapping[str, Any], ...] = ()
    type_hash: str | None = None
    message_count: int | None = None


@dataclass(frozen=True)
class Recording:
    """A recording as read: ``shown`` is its path for messages; ``storage`` ``sqlite3`` or ``mcap``;
    ``version`` the metadata version (None: a plain file without rosbag2 metadata); ``notes`` what
    the reader could not read and why (a compressed file, counts from the metadata)."""

    path: Path
    shown: str
    storage: str
    topics: tuple[RecordedTopic, ...]
    version: int | None = None
    ros_distro: str | None = None
    files: tuple[str, ...] = ()
    notes: tuple[str, ...] = field(default_factory=tuple)

    def topic(self, name: str) -> RecordedTopic | None:
        for topic in self.topics:
            if topic.name == name:
                return topic
        return None

    @property
    def message_count(self) -> int:
        return sum(t.message_count or 0 for t in self.topics)


# ---------------------------------------------------------------------------- QoS


def _yaml(text: str, where: str, what: str) -> Any:
    """A YAML document read as any untrusted file is (``model.untrusted``: bounded nesting and
    expansion, unique string keys); raises RecordingError naming ``where`` and ``what``."""
    try:
        root = untrusted.compose_yaml(text)
        if root is None:
            return None
        untrusted.check_tree(root)
        return untrusted.construct(root)
    except InputError as exc:
        at = f" (line {exc.line})" if exc.line else ""
        raise RecordingError(f"{where}: {what} cannot be read{at}: {exc.reason}") from None


def _enum(policy: str, value: Any, where: str) -> str:
    if isinstance(value, bool):
        raise RecordingError(f"{where}: QoS {policy} {value!r} is not a policy value")
    if isinstance(value, int):
        if value not in _ENUMS[policy]:
            raise RecordingError(f"{where}: QoS {policy} {value} is not one of rmw's values")
        return _ENUMS[policy][value]
    if isinstance(value, str):
        word = value.strip().upper()
        if word.isdigit():
            return _enum(policy, int(word), where)
        if word == "MANUAL_BY_NODE":
            return "UNKNOWN"
        if word in _ENUMS[policy].values():
            return word
    raise RecordingError(f"{where}: QoS {policy} {value!r} is not one of rmw's values")


def _duration(policy: str, value: Any, where: str) -> int:
    if value is None:
        return 0
    if isinstance(value, Mapping):
        sec, nsec = value.get("sec", 0), value.get("nsec", 0)
        if isinstance(sec, int) and isinstance(nsec, int) and not isinstance(sec, bool) and not isinstance(nsec, bool):
            if (sec, nsec) in _INFINITE:
                return -1
            return sec * _SECOND + nsec
    if isinstance(value, int) and not isinstance(value, bool):
        return value
    raise RecordingError(f"{where}: QoS {policy} {value!r} is not a duration ({{sec: S, nsec: N}})")


def parse_qos_profile(profile: Any, where: str) -> dict[str, Any]:
    """One offered QoS profile as rosbag2 writes it → the raw capture form of ``model.qos``."""
    if not isinstance(profile, Mapping):
        raise RecordingError(f"{where}: an offered QoS profile is not a mapping: {profile!r}")
    out: dict[str, Any] = {}
    for policy in _ENUMS:
        if policy in profile:
            out[policy] = _enum(policy, profile[policy], where)
    depth = profile.get("depth")
    if isinstance(depth, int) and not isinstance(depth, bool) and depth >= 0:
        out["depth"] = depth
    for policy, key in _DURATIONS.items():
        if policy in profile:
            out[key] = _duration(policy, profile[policy], where)
    avoid = profile.get("avoid_ros_namespace_conventions")
    if isinstance(avoid, bool):
        out["avoid_ros_namespace_conventions"] = avoid
    return out


def parse_qos_profiles(value: Any, where: str) -> tuple[dict[str, Any], ...]:
    """``offered_qos_profiles``: a YAML string (metadata up to version 8, sqlite3's column, MCAP's
    channel metadata) or a list (metadata version 9)."""
    if value is None or value == "":
        return ()
    if isinstance(value, str):
        value = _yaml(value, where, "offered_qos_profiles (YAML)")
        if value is None:
            return ()
    if not isinstance(value, list):
        raise RecordingError(f"{where}: offered_qos_profiles is not a list of QoS profiles")
    return tuple(parse_qos_profile(p, where) for p in value)


# ---------------------------------------------------------------------------- storage files


def _what_to_do(kind: str) -> str:
    if kind == "mcap":
        return ("if the recording was cut short, `ros2 bag reindex` (or `mcap recover`) may rebuild it; "
                "otherwise record again")
    return "if the recording was cut short, `ros2 bag reindex` may rebuild it; otherwise record again"


def read_sqlite(path: Path, shown: str) -> list[RecordedTopic]:
    """The topics of a rosbag2 sqlite3 file, with their message counts."""
    if not path.is_file():
        raise RecordingError(f"{shown}: not found (the recording's storage file is missing); "
                             "check the path, or copy the whole bag directory")
    try:
        with open(path, "rb") as probe:
            magic = probe.read(16)
    except OSError as exc:
        raise RecordingError(f"{shown}: cannot be read ({exc.strerror or exc})") from None
    if magic != b"SQLite format 3\x00":
        raise RecordingError(f"{shown}: not an SQLite database (rosbag2's sqlite3 storage): the file is corrupt "
                             f"or of another format; {_what_to_do('sqlite3')}")
    try:
        db = sqlite3.connect(f"{path.absolute().as_uri()}?mode=ro", uri=True)
    except sqlite3.Error as exc:
        raise RecordingError(f"{shown}: cannot be opened as an SQLite database ({exc})") from None
    try:
        columns = {row[1] for row in db.execute("PRAGMA table_info(topics)")}
        if not {"id", "name", "type"} <= columns:
            raise RecordingError(f"{shown}: an SQLite database without rosbag2's `topics` table: not a rosbag2 "
                                 "sqlite3 recording")
        wanted = ["id", "name", "type",
                  "serialization_format" if "serialization_format" in columns else "'cdr'",
                  "offered_qos_profiles" if "offered_qos_profiles" in columns else "''",
                  "type_description_hash" if "type_description_hash" in columns else "''"]
        rows = db.execute(f"SELECT {', '.join(wanted)} FROM topics ORDER BY id").fetchall()
        counts = dict(db.execute("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id").fetchall())
    except (sqlite3.DatabaseError, UnicodeDecodeError) as exc:  # a damaged page can hold any bytes
        raise RecordingError(f"{shown}: the SQLite database cannot be read ({exc}): the file is corrupt or "
                             f"truncated; {_what_to_do('sqlite3')}") from None
    finally:
        db.close()
    topics = []
    for topic_id, name, type_name, fmt, profiles, type_hash in rows:
        where = f"{shown}: topic {name}"
        topics.append(RecordedTopic(name=str(name), type=str(type_name), serialization_format=str(fmt or "cdr"),
                                    qos_profiles=parse_qos_profiles(profiles, where),
                                    type_hash=str(type_hash) if type_hash else None,
                                    message_count=int(counts.get(topic_id, 0))))
    return topics


def read_mcap(path: Path, shown: str) -> tuple[list[RecordedTopic], int | None, str | None]:
    """The topics of an MCAP file with their message counts, the rosbag2 metadata version it
    carries (None without) and its ROS distribution."""
    if not path.is_file():
        raise RecordingError(f"{shown}: not found (the recording's storage file is missing); "
                             "check the path, or copy the whole bag directory")
    try:
        with open(path, "rb") as stream:
            reader = make_reader(stream)
            summary = reader.get_summary()
            if summary is None or summary.statistics is None:
                raise RecordingError(f"{shown}: the MCAP file has no summary (its end is missing): the recording was "
                                     f"cut short or the file truncated; {_what_to_do('mcap')}")
            metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    except RecordingError:
        raise
    except OSError as exc:
        raise RecordingError(f"{shown}: cannot be read ({exc.strerror or exc})") from None
    except Exception as exc:  # the library's parser meets any bytes: besides its McapError, each release raises
        # other types on a bad file (OverflowError, struct.error, EOFError, a codec's errors)
        why = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
        raise RecordingError(f"{shown}: not a readable MCAP file ({why}): the file is corrupt "
                             f"or truncated; {_what_to_do('mcap')}") from None
    version: int | None = None
    distro: str | None = None
    rosbag2 = metadata.get("rosbag2", {})
    if rosbag2.get("serialized_metadata"):
        try:  # it only says the metadata version and distribution: a broken one is not needed
            info = _yaml(rosbag2["serialized_metadata"], shown, "the rosbag2 metadata record")
        except RecordingError:
            info = None
        if isinstance(info, Mapping):
            info = info.get("rosbag2_bagfile_information", info)
            version = info.get("version") if isinstance(info.get("version"), int) else None
            distro = info.get("ros_distro") if isinstance(info.get("ros_distro"), str) else None
    distro = distro or rosbag2.get("ROS_DISTRO")
    counts = summary.statistics.channel_message_counts
    topics = []
    for channel_id, channel in sorted(summary.channels.items()):
        schema = summary.schemas.get(channel.schema_id)
        where = f"{shown}: topic {channel.topic}"
        topics.append(RecordedTopic(
            name=channel.topic, type=schema.name if schema is not None else "",
            serialization_format=channel.message_encoding or "cdr",
            qos_profiles=parse_qos_profiles(channel.metadata.get("offered_qos_profiles"), where),
            type_hash=channel.metadata.get("topic_type_hash") or None,
            message_count=int(counts.get(channel_id, 0))))
    return topics, version, distro


# ---------------------------------------------------------------------------- a bag directory


def _metadata(directory: Path, shown: str) -> Mapping[str, Any]:
    file = directory / METADATA_FILE
    where = display(file)
    try:
        text = untrusted.read_text(file)
    except (OSError, InputError) as exc:
        reason = exc.reason if isinstance(exc, InputError) else exc.strerror or str(exc)
        raise RecordingError(f"{where}: cannot be read ({reason})") from None
    document = _yaml(text, where, f"the metadata (`ros2 bag reindex {shown}` writes it anew)")
    info = document.get("rosbag2_bagfile_information") if isinstance(document, Mapping) else None
    if not isinstance(info, Mapping):
        raise RecordingError(f"{where}: not rosbag2 metadata (no `rosbag2_bagfile_information:`); "
                             f"`ros2 bag reindex {shown}` writes it anew")
    return info


def _metadata_topics(info: Mapping[str, Any], version: int, where: str) -> list[RecordedTopic]:
    entries = info.get("topics_with_message_count") or []
    if not isinstance(entries, list):
        raise RecordingError(f"{where}: `topics_with_message_count` is not a list")
    topics = []
    for entry in entries:
        meta = entry.get("topic_metadata") if isinstance(entry, Mapping) else None
        if not isinstance(meta, Mapping) or not isinstance(meta.get("name"), str):
            raise RecordingError(f"{where}: an entry of `topics_with_message_count` has no `topic_metadata` name")
        count = entry.get("message_count")
        type_hash = meta.get("type_description_hash") if version >= 7 else None
        topics.append(RecordedTopic(
            name=meta["name"], type=str(meta.get("type") or ""),
            serialization_format=str(meta.get("serialization_format") or "cdr"),
            qos_profiles=parse_qos_profiles(meta.get("offered_qos_profiles"), f"{where}: topic {meta['name']}"),
            type_hash=str(type_hash) if type_hash else None,
            message_count=count if isinstance(count, int) and not isinstance(count, bool) else None))
    return topics


def _merge(from_metadata: Sequence[RecordedTopic], from_files: Sequence[RecordedTopic] | None) -> list[RecordedTopic]:
    """The metadata's topics, what the files add (topics, hashes, QoS) and the files' counts."""
    if from_files is None:
        return list(from_metadata)
    counts: dict[str, int] = {}
    found: dict[str, RecordedTopic] = {}
    for topic in from_files:
        counts[topic.name] = counts.get(topic.name, 0) + (topic.message_count or 0)
        found.setdefault(topic.name, topic)
    out = []
    for topic in from_metadata:
        other = found.pop(topic.name, None)
        out.append(RecordedTopic(
            name=topic.name, type=topic.type or (other.type if other else ""),
            serialization_format=topic.serialization_format,
            qos_profiles=topic.qos_profiles or (other.qos_profiles if other else ()),
            type_hash=topic.type_hash or (other.type_hash if other else None),
            message_count=counts.get(topic.name, 0) if other is not None else topic.message_count))
    for name, other in found.items():
        out.append(RecordedTopic(name=name, type=other.type, serialization_format=other.serialization_format,
                                 qos_profiles=other.qos_profiles, type_hash=other.type_hash,
                                 message_count=counts[name]))
    return out


def _read_directory(directory: Path, shown: str) -> Recording:
    if not (directory / METADATA_FILE).is_file():
        stores = sorted(p.name for p in directory.iterdir() if p.suffix in (".mcap", ".db3")) if directory.is_dir() else []
        hint = (f"; it holds {', '.join(stores)}: give that file itself (--bag {display(directory / stores[0])}), or "
                f"write the metadata with `ros2 bag reindex {shown}`" if stores else
                "; give a rosbag2 bag directory (the one `ros2 bag record -o DIR` wrote) or an .mcap file")
        raise RecordingError(f"{shown}: a directory without {METADATA_FILE}, so not a rosbag2 recording{hint}")
    where = display(directory / METADATA_FILE)
    info = _metadata(directory, shown)
    version = info.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or version < 1:
        raise RecordingError(f"{where}: no metadata `version:` (an integer); `ros2 bag reindex {shown}` writes it anew")
    storage = info.get("storage_identifier")
    if storage not in STORAGES:
        raise RecordingError(f"{where}: storage `{storage}` is not one this check reads ({', '.join(STORAGES)}); "
                             f"convert the recording (`ros2 bag convert` to sqlite3 or mcap) and check that")
    files = info.get("relative_file_paths") or []
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        raise RecordingError(f"{where}: `relative_file_paths` is not a list of file names")
    compressed = str(info.get("compression_mode") or "").lower() == "file" and info.get("compression_format")
    notes: list[str] = []
    from_files: list[RecordedTopic] | None = []
    for name in files:
        file = directory / name
        file_shown = display(file)
        if not file.is_file():
            raise RecordingError(f"{file_shown}: missing: {where} lists it among the recording's files; copy the whole "
                                 "bag directory (or fix `relative_file_paths`)")
        if compressed:
            continue
        if storage == "mcap":
            topics, _, _ = read_mcap(file, file_shown)
        else:
            topics = read_sqlite(file, file_shown)
        assert from_files is not None
        from_files += topics
    if compressed:
        from_files = None
        notes.append(f"its files are compressed ({info.get('compression_format')}): topics, QoS and counts are "
                     f"{METADATA_FILE}'s, the files were not read")
    distro = info.get("ros_distro") if isinstance(info.get("ros_distro"), str) else None
    return Recording(path=directory, shown=shown, storage=str(storage),
                     topics=tuple(_merge(_metadata_topics(info, version, where), from_files)),
                     version=version, ros_distro=distro or None, files=tuple(files), notes=tuple(notes))


def read(path: str | os.PathLike[str]) -> Recording:
    """Read the recording at ``path``: a rosbag2 bag directory, an ``.mcap`` or a ``.db3`` file.
    Raises RecordingError."""
    p = Path(path)
    shown = display(p)
    if p.is_dir():
        return _read_directory(p, shown)
    if not p.exists():
        raise RecordingError(f"{shown}: no such file or directory; give a rosbag2 bag directory (with "
                             f"{METADATA_FILE}) or an .mcap file")
    if p.suffix == ".mcap":
        topics, version, distro = read_mcap(p, shown)
        return Recording(path=p, shown=shown, storage="mcap", topics=tuple(topics), version=version,
                         ros_distro=distro, files=(p.name,))
    if p.suffix == ".db3":
        return Recording(path=p, shown=shown, storage="sqlite3", topics=tuple(read_sqlite(p, shown)), files=(p.name,))
    if p.name == METADATA_FILE:
        return _read_directory(p.parent, display(p.parent))
    raise RecordingError(f"{shown}: not a recording this check reads: give a rosbag2 bag directory (with "
                         f"{METADATA_FILE}), an .mcap or a .db3 file")
