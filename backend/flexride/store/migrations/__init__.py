"""Alembic migrations of the job store (run by :func:`flexride.store.db.init_db`).

New revision: ``alembic -c backend/flexride/store/migrations/alembic.ini revision -m "..."``
(write the operations by hand or with ``--autogenerate`` against a database at head).
"""
