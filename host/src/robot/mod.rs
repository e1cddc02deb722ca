//! Models of the robot's hardware on the host: the coreless DC motor, the
//! Li-Po cell and the PWM drive, used by the controller tests and by `swimbot sim`.
