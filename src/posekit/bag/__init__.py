"""Recording and playback as ROS 2 bags: rosbag2 directories in MCAP storage, via rosbags.

    from posekit.bag import Recorder, Player, bag_info, read_messages

* :class:`Recorder` / :func:`attach_recorder` / :func:`record_scenario`: a node that writes
  topics into a new bag (zstd-compressed MCAP chunks, metadata.yaml version 9 or 8, the
  offered QoS per topic, full message definitions for Foxglove and ``ros2 bag``).
* :class:`Player`: publishes a bag on its recorded time line with ``/clock`` (stepped in a
  SimulatedTimeExecutor, or in wall-clock time at a rate, optionally looping).
* :func:`bag_info` / :func:`format_info`: ``ros2 bag info``; :func:`read_messages`: iterate.
* :func:`reindex`: ``ros2 bag reindex``: a complete bag from what a killed recorder left.

rosbags is imported when one of these runs, not on ``import posekit.bag``. See docs/bags.md.
"""

from __future__ import annotations

from posekit.bag.errors import (
    BagError,
    BagExistsError,
    BagFormatError,
    BagNotFoundError,
    BagOptionError,
)
from posekit.bag.info import BagInfo, TopicInfo, bag_info, format_info
from posekit.bag.player import PlaybackTopic, Player
from posekit.bag.reader import BagMessage, read_messages
from posekit.bag.recorder import Recorder, attach_recorder, record_scenario
from posekit.bag.reindex import ReindexResult, reindex

__all__ = [
    "BagError",
    "BagExistsError",
    "BagFormatError",
    "BagInfo",
    "BagMessage",
    "BagNotFoundError",
    "BagOptionError",
    "PlaybackTopic",
    "Player",
    "Recorder",
    "ReindexResult",
    "TopicInfo",
    "attach_recorder",
    "bag_info",
    "format_info",
    "read_messages",
    "record_scenario",
    "reindex",
]
