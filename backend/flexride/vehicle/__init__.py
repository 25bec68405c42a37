"""The vehicle: bodies, suspension elements and recorded points."""
