"""3-PSR wave and boat-motion replicator: kinematics, workspace, design optimization, wave profiles and the platform node."""
