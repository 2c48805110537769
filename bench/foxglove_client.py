"""A client of Foxglove's WebSocket protocol for tests and benches: what the Foxglove app sends."""

from collections import defaultdict
from contextlib import ExitStack
import json
import socket
import struct

from websockets.sync.client import connect

# The subprotocol foxglove-sdk's server speaks (the app's foxglove.websocket.v1, renamed).
SUBPROTOCOL = 'foxglove.sdk.v1'
MESSAGE_DATA = 0x01
# A client that stopped reading sees the server's closing frame only behind what was queued for
# it: its close waits this long (s) for it (the library's 10 s held every such test).
CLOSE_TIMEOUT = 1.0


class FoxgloveClient:
    """
    Connects to a server on localhost; poll() takes in what has arrived, without waiting.

    channels holds the advertised channels by topic, messages each subscribed topic's
    (log time, payload) pairs, statuses the server's status messages. receive_buffer, if
    given, shrinks the socket's buffer, to make a slow client. It sends no keepalive pings: a
    client that reads nothing would see no pong behind the data queued for it and close itself.
    """

    def __init__(self, port, receive_buffer=None):
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if receive_buffer is not None:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, receive_buffer)
        sock.settimeout(10.0)
        sock.connect(('127.0.0.1', port))
        self._connection = ExitStack()
        self.socket = self._connection.enter_context(connect(
            f'ws://127.0.0.1:{port}', sock=sock, subprotocols=[SUBPROTOCOL], open_timeout=10.0,
            max_size=None, ping_interval=None, close_timeout=CLOSE_TIMEOUT))
        self.server_info = None
        self.channels = {}
        self.messages = defaultdict(list)
        self.statuses = []
        self._topics_by_subscription = {}
        self._next_id = 1

    def poll(self):
        """Take in every frame received so far."""
        while True:
            try:
                frame = self.socket.recv(timeout=0)
            except TimeoutError:
                return
            if isinstance(frame, str):
                self._take_text(json.loads(frame))
            elif frame[0] == MESSAGE_DATA:
                subscription, log_time = struct.unpack_from('<IQ', frame, 1)
                topic = self._topics_by_subscription.get(subscription)
                if topic is not None:
                    self.messages[topic].append((log_time, bytes(frame[13:])))

    def _take_text(self, message):
        if message['op'] == 'serverInfo':
            self.server_info = message
        elif message['op'] == 'advertise':
            self.channels.update({channel['topic']: channel for channel in message['channels']})
        elif message['op'] == 'unadvertise':
            gone = set(message['channelIds'])
            self.channels = {topic: channel for topic, channel in self.channels.items()
                             if channel['id'] not in gone}
        elif message['op'] == 'status':
            self.statuses.append(message)

    def _new_id(self):
        self._next_id += 1
        return self._next_id

    def subscribe(self, *topics):
        """Subscribe to the channels of topics; return their subscription ids."""
        subscriptions = [{'id': self._new_id(), 'channelId': self.channels[topic]['id']}
                         for topic in topics]
        for subscription, topic in zip(subscriptions, topics):
            self._topics_by_subscription[subscription['id']] = topic
        self.send({'op': 'subscribe', 'subscriptions': subscriptions})
        return [subscription['id'] for subscription in subscriptions]

    def unsubscribe(self, *subscription_ids):
        self.send({'op': 'unsubscribe', 'subscriptionIds': list(subscription_ids)})

    def advertise(self, topic, schema_name, encoding='cdr'):
        """Advertise a channel to publish on, as the Teleop panel does; return its id."""
        channel_id = self._new_id()
        self.send({'op': 'advertise', 'channels': [
            {'id': channel_id, 'topic': topic, 'encoding': encoding, 'schemaName': schema_name}]})
        return channel_id

    def publish(self, channel_id, payload):
        self.socket.send(struct.pack('<BI', MESSAGE_DATA, channel_id) + payload)

    def send(self, message):
        self.socket.send(json.dumps(message))

    def vanish(self):
        """Drop the connection as a crashed client does: no closing handshake."""
        self.socket.socket.shutdown(socket.SHUT_RDWR)
        self.socket.socket.close()

    def close(self):
        self._connection.close()
