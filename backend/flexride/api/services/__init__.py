"""What the routes call: job, study, result and health operations on the store and runner."""
