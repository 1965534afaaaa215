"""Stresses on the boundary and inside the bodies: Somigliana, half-plane and closed forms."""
