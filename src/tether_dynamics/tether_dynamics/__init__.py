"""Tether statics (``statics``), finite-element dynamics (``fem``), the tether plant with a
moving reel (``plant``), and their command-line and plotting code (``commands``).
"""
