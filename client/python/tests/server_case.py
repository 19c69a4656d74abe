"""The server a test module talks to: run_with_server.py starts one and names it in
MBSTREAM_SERVER; without it the module's tests are skipped."""
import os
import unittest

import mbstream_client as mb


class ServerTestCase(unittest.TestCase):
    """A test case with `client` connected to the server at MBSTREAM_SERVER (`address`)."""
    address: str
    client: mb.Client

    @classmethod
    def setUpClass(cls) -> None:
        cls.address = os.environ.get("MBSTREAM_SERVER", "")
        if not cls.address:
            raise unittest.SkipTest("set MBSTREAM_SERVER (run_with_server.py does)")
        cls.client = mb.connect(cls.address)

    @classmethod
    def tearDownClass(cls) -> None:
        cls.client.close()
