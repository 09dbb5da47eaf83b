"""Rewrite a damaged bag as a finalized one, as ``ros2 bag reindex`` and ``mcap recover`` do.

Everything intact in the damaged file (:func:`tether_bringup.bag_reader.read_bag`: only chunks
that pass their CRC check) is written anew by the recorder's writer, with the bag's own message definitions, QoS and type hashes:
chunks, indexes, Statistics, the rosbag2 metadata record and ``metadata.yaml``. The damaged
file is kept beside it as ``<name>.damaged``, so nothing is thrown away.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from tether_bringup.bag_reader import Bag
from tether_bringup.bag_reader import read_bag
from tether_bringup.bag_writer import BagWriter
from tether_bringup.errors import BagError


@dataclass
class Recovery:
    """What a recovery did: the damage it found, the finalized file, the damaged one kept."""

    bag: Bag
    damaged_copy: Path

    def line(self) -> str:
        """One line for the user: what was damaged, what the finalized bag holds, where the original is."""
        lost = self.bag.lost_count
        dropped = 'an unknown number of messages' if lost is None else f'{lost} messages'
        return (f'recovered {self.bag.path}: {len(self.bag.messages)} messages on {len(self.bag.topics)} topics '
                f'over {self.bag.duration:.3f} s rewritten as a finalized bag, {dropped} dropped from '
                f'{len(self.bag.damage)} damaged place(s), the first at {self.bag.damage[0]}; the damaged file is '
                f'kept as {self.damaged_copy.name}')


def recover_bag(path: str | Path) -> Recovery | None:
    """Rewrite the bag at ``path`` as a finalized one if it is damaged; return None if it is not.

    Raises:
        BagError: nothing in the file is recoverable, or the damaged copy's name is taken.
    """
    bag = read_bag(path, allow_damaged=True)
    if bag.complete:
        return None
    damaged_copy = bag.path.with_name(bag.path.name + '.damaged')
    if damaged_copy.exists():
        raise BagError(f'{damaged_copy}: already exists; move it away to recover {bag.path} again')
    scratch = bag.path.parent / f'.{bag.path.stem}.recovering'
    shutil.rmtree(scratch, ignore_errors=True)
    writer = BagWriter(scratch, file_name=bag.path.name)
    try:
        for topic in bag.topics.values():
            writer.add_topic(topic.name, topic.type_name, topic.qos, topic.type_hash, definition=topic.definition)
        for message in bag.messages:
            writer.write(message.topic, message.data, message.log_time, message.publish_time)
        writer.close()
        os.replace(bag.path, damaged_copy)
        os.replace(writer.path, bag.path)
        if bag.path.name == f'{bag.path.parent.name}_0.mcap' or (bag.path.parent / 'metadata.yaml').exists():
            os.replace(scratch / 'metadata.yaml', bag.path.parent / 'metadata.yaml')
    except OSError as error:
        raise BagError(f'{bag.path}: cannot write the recovered bag ({error.strerror})') from None
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return Recovery(bag, damaged_copy)
