"""Revisions of the job store's tables, oldest first by their ``down_revision`` chain."""
