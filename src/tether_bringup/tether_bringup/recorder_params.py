"""Parameters of the recorder node (no rclpy import; shared with the scene validator)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec

DEFAULT_EXCLUDE = ('/rosout', '/parameter_events')
"""Topics a run does not record unless its scene says otherwise: ROS's own log and parameter events."""

LIVE_HOST = '127.0.0.1'
"""The live server listens on this machine only unless asked for another address."""
LIVE_PORT = 8765
"""The Foxglove WebSocket protocol's usual port (foxglove_bridge's, the apps' default)."""

PARAMETERS = (
    ParamSpec('bag_directory', 'bag', 'Directory of the rosbag2 bag to write (created)'),
    ParamSpec('exclude', list(DEFAULT_EXCLUDE), 'Topics not recorded'),
    ParamSpec('expected_nodes', [], 'Node names to wait for before reporting ready', item_type=str),
    ParamSpec('ready_file', '', 'File written with the recorded topics once subscribed'),
    ParamSpec('discovery_period', 0.1, 'Period of the topic discovery', 's', 0.01, 5.0),
    ParamSpec('settle_time', 1.0, 'Quiet time of the graph before reporting ready', 's', 0.0, 10.0),
    ParamSpec('flush_period', 1.0, 'Longest time data waits in an unwritten chunk', 's', 0.05, 10.0),
    ParamSpec('chunk_period', 1.0, 'Sim time one chunk spans at most: what one damaged chunk costs', 's', 0.01, 60.0),
    ParamSpec('queue_depth', 1000, 'Subscription queue depth per topic', '', 1, 100000),
    ParamSpec('stream_fd', -1, 'Read end of the node group\'s recording stream (a pipe), -1 for none', '', -1, 65535),
    ParamSpec('stream_nodes', [], 'Fully qualified names of the node group\'s nodes, whose topics come from '
              'stream_fd', item_type=str),
    ParamSpec('live_port', -1, 'Port of the live Foxglove WebSocket server (tether_bringup.live_server): -1 none, '
              '0 any free one', '', -1, 65535),
    ParamSpec('live_host', LIVE_HOST, 'Address the live server listens on'),
    ParamSpec('live_wait', False, 'Report ready only once a client has subscribed to the live server'),
    ParamSpec('live_stats_file', '', 'File the live server writes its URL to once every topic is advertised, and its statistics at stop'),
)
