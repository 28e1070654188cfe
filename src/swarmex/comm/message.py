"""What every radio message here shares: a type name, a msgpack-ready dict, its size.

The exploration mission's messages and AODV's control messages are both sized by their
msgpack encoding (what the networked runtime would send, and what ``bytes_sent`` adds up),
so they share this base instead of each carrying its own copy.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar, Generic, TypeVar, overload

import msgpack

T = TypeVar("T")


class once(Generic[T]):
    """A property computed on first read and then stored on the instance.

    What :func:`functools.cached_property` does, without the lock Python 3.11 takes on every
    first read (a flood of n robots makes n relays, each sized once: the lock was a third of
    the sizing cost). A non-data descriptor: once the value is in the instance's
    ``__dict__``, reads are plain attribute lookups that never reach this class.
    """

    def __init__(self, fn: Callable[[Any], T]) -> None:
        self.fn = fn
        self.name = fn.__name__
        self.__doc__ = fn.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, obj: None, owner: type | None = None) -> once[T]: ...

    @overload
    def __get__(self, obj: object, owner: type | None = None) -> T: ...

    def __get__(self, obj: object | None, owner: type | None = None) -> T | once[T]:
        if obj is None:
            return self
        value = obj.__dict__[self.name] = self.fn(obj)
        return value


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

    @once
    def nbytes(self) -> int:
        return packed_size(self.to_dict())
