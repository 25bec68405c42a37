"""Running jobs and studies: resolve and check scenarios, expand studies into job matrices,
submit them, run one job end to end (:mod:`~flexride.study.run_job`) and aggregate study
results into tables.
"""
