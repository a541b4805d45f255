"""MCAP files of armplan messages: JSON messages on channels with JSON schemas."""

from shared.recording.reader import Record, read_records, summarize
from shared.recording.writer import MessageWriter

__all__ = ["MessageWriter", "Record", "read_records", "summarize"]
