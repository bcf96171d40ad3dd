"""hfi-sensorless golden model: the executable specification, the plant and the closed-loop simulator."""
