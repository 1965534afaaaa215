"""Closed forms, Nowell-Hills, and the result checks applied to every step."""
