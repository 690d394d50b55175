"""The PoKeys language: 64-byte request/reply frames over TCP, UDP and discovery."""

from .packet import Reply, Request, checksum, make_request, parse_request
from .session import PoKeysSession
from .table import ENTRIES, CommandEntry, dispatch, lookup

__all__ = ["ENTRIES", "CommandEntry", "PoKeysSession", "Reply", "Request", "checksum",
           "dispatch", "lookup", "make_request", "parse_request"]
