"""The texture bank (thesis §5.4.2): textures kept as their recipe, searched by words, tags,
attributes and likeness, with its command line.
"""

from .attributes import Attributes
from .store import Bank, BankError, Entry

__all__ = ["Attributes", "Bank", "BankError", "Entry"]
