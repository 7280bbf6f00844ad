"""lidarscout.Error: what the library's lidarscout::Error says (the file, the byte offset, the cause)."""


class Error(RuntimeError):
    """A bad input or request: ``file`` (or None), ``offset`` (bytes, or None) and ``cause``."""

    def __init__(self, message, file=None, offset=None, cause=None):
        super().__init__(message)
        self.file = file
        self.offset = offset
        self.cause = cause if cause is not None else message
