"""Contact between two faces: pairs, pairing, the unknowns, condensation, laws and zones.

The names of :mod:`.pairs` are re-exported here.
"""

from .pairing import Pairing
from .pairs import (
    SEPARATED,
    SLIP,
    STATE_NAMES,
    STICK,
    ContactDiscretisationError,
    ContactPair,
    NodeToNodePair,
)

__all__ = [
    "SEPARATED",
    "SLIP",
    "STATE_NAMES",
    "STICK",
    "ContactDiscretisationError",
    "ContactPair",
    "NodeToNodePair",
    "Pairing",
]
