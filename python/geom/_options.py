"""Keyword arguments → the compiled options structs, with one error message for unknown names."""

__all__ = []


def make(options_type, kwargs):
    """An instance of ``options_type`` (a bound C++ options struct) with ``kwargs`` applied.

    Keyword names are the C++ field names. An unknown name raises TypeError listing the known
    ones; a value of the wrong type raises TypeError from the binding; a value outside the
    documented domain raises ValueError from the library when the options are used.
    """
    options = options_type()
    for name, value in kwargs.items():
        if name.startswith("_") or not hasattr(options, name):
            known = ", ".join(n for n in dir(options) if not n.startswith("_"))
            raise TypeError(f"unknown option {name!r} for {options_type.__name__} "
                            f"(expected one of: {known})")
        setattr(options, name, value)
    return options
