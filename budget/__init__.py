"""sar-imu-budget: IMU grade selection and error budgets for synthetic-aperture radar and sonar."""

__version__ = "0.1.0"
