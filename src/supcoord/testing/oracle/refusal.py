"""The oracle's refusal: a problem it cannot take."""

from __future__ import annotations

from ...errors import InputError

__all__ = ["OracleInputError"]


class OracleInputError(InputError):
    """A problem the oracle cannot take (missing field, out of range, colliding start)."""
