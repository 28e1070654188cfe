"""What every radio message here shares: a type name, a msgpack-ready dict, its size.

The exploration mission's messages and AODV's control messages are both sized by their
msgpack encoding (what the networked runtime would send, and what ``bytes_sent`` adds up),
so they share this base instead of each carrying its own copy.
"""

from __future__ import annotations

from functools import cached_property
from typing import Any, ClassVar

import msgpack


def packed_size(d: dict[str, Any]) -> int:
    """Bytes of ``d``'s msgpack encoding."""
    return len(msgpack.packb(d, use_bin_type=True))


class PackedMessage:
    """A message: ``kind`` (its type name), ``body()`` (its fields), ``to_dict()`` and
    ``nbytes`` (computed once: messages are immutable once sent)."""

    kind: ClassVar[str] = ""

    def body(self) -> dict[str, Any]:
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.kind, **self.body()}

    @cached_property
    def nbytes(self) -> int:
        return packed_size(self.to_dict())
