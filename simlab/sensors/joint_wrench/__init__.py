"""The joint wrench sensor: the wrench each body of an articulation receives through its joint."""

from .joint_wrench_sensor import JointWrenchSensor, JointWrenchSensorCfg, JointWrenchSensorData

__all__ = ["JointWrenchSensor", "JointWrenchSensorCfg", "JointWrenchSensorData"]
