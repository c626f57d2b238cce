"""Keywords of the public API renamed for one name per concept (issue 34 item 5): the old
name keeps working for one release with a DeprecationWarning that names the new one
(docs/decisions.md, "Issue 34 ... fifth session")."""

from __future__ import annotations

import functools
import warnings

__all__ = ["renamed"]


def renamed(**old_to_new: str):
    """Decorator: each keyword ``old`` of the call is passed on as ``old_to_new[old]``, with a
    DeprecationWarning pointing at the caller's line.  Both given is a TypeError, as Python's
    own "got multiple values for argument"."""
    def decorate(function):
        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            for old, new in old_to_new.items():
                if old not in kwargs:
                    continue
                if new in kwargs:
                    raise TypeError(f"{function.__name__}() got both '{old}' and '{new}' "
                                    f"('{old}' is the old name of '{new}')")
                warnings.warn(f"{function.__name__}(): the keyword '{old}' is deprecated, use "
                              f"'{new}' (the same value)", DeprecationWarning, stacklevel=2)
                kwargs[new] = kwargs.pop(old)
            return function(*args, **kwargs)
        return wrapper
    return decorate
