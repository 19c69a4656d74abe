"""Shared bits of the examples. They import the installed package (pip install
./client/python, see ../README.md), never this source folder."""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


def model_file(*parts):
    """A path below the repository's models/ folder."""
    return os.path.join(REPO, "models", *parts)


def add_server_argument(parser):
    parser.add_argument("--server", default=os.environ.get("MBSTREAM_SERVER", "127.0.0.1:50051"),
                        help="server address host:port or unix:/path (default "
                             "$MBSTREAM_SERVER or 127.0.0.1:50051)")
    parser.add_argument("--ca", help="PEM CA of the server's certificate (TLS)")
    parser.add_argument("--token", default=os.environ.get("MBSTREAM_TOKEN"),
                        help="access token (default $MBSTREAM_TOKEN)")
