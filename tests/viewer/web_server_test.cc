// The --web server on its own (no viewer, no browser): the page's files and nothing else,
// refusals of malformed and unexpected requests, the snapshot on connect, the page limit,
// a stalled page that never slows another, the page's replay controls, HTTPS/WSS with
// --web-tls, and the token check before a page gets anything.
#include <gmock/gmock.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "viewer/web/web_server.h"
#include "viewer/web/web_view.h"

namespace mbstream::viewer {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using ::testing::HasSubstr;

class WebServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    WebOptions options;
    options.max_pages = 2;
    Restart(std::move(options));
  }
  tcp::socket Connect() {
    tcp::socket socket(ioc_);
    tcp::resolver resolver(ioc_);
    asio::connect(socket, resolver.resolve("127.0.0.1", port_));
    return socket;
  }
  http::response<http::string_body> Request(http::verb verb, const std::string& target) {
    beast::tcp_stream stream(Connect());
    http::request<http::string_body> request(verb, target, 11);
    request.set(http::field::host, "127.0.0.1");
    http::write(stream, request);
    beast::flat_buffer buffer;
    http::response<http::string_body> response;
    http::read(stream, buffer, response);
    return response;
  }
  std::unique_ptr<websocket::stream<tcp::socket>> Page() {
    auto ws = std::make_unique<websocket::stream<tcp::socket>>(Connect());
    ws->handshake("127.0.0.1", "/ws");
    return ws;
  }
  static std::string Read(websocket::stream<tcp::socket>& ws) {
    beast::flat_buffer buffer;
    ws.read(buffer);
    return beast::buffers_to_string(buffer.data());
  }

  // Restarts the server with `options` (the root and the address as SetUp's).
  void Restart(WebOptions options) {
    server_.reset();
    options.address = "127.0.0.1:0";
    options.root = MBSTREAM_WEB_ROOT;
    server_ = std::make_unique<WebServer>(std::move(options), [this](const std::string& json) {
      std::lock_guard<std::mutex> lock(controls_mutex_);
      controls_.push_back(json);
      controls_changed_.notify_all();
      return true;
    });
    server_->Start();
    const std::string url = server_->url();
    port_ = url.substr(url.rfind(':') + 1, url.size() - url.rfind(':') - 2);
  }

  // The controls the server passed on (its thread), once there are `count` (or 30 s passed).
  std::vector<std::string> Controls(std::size_t count) {
    std::unique_lock<std::mutex> lock(controls_mutex_);
    controls_changed_.wait_for(lock, std::chrono::seconds(30),
                               [&] { return controls_.size() >= count; });
    return controls_;
  }

  asio::io_context ioc_;
  std::unique_ptr<WebServer> server_;
  std::string port_;
  std::mutex controls_mutex_;
  std::condition_variable controls_changed_;
  std::vector<std::string> controls_;
};

TEST_F(WebServerTest, ServesThePageAndThreeJsAndNothingElse) {
  const auto page = Request(http::verb::get, "/");
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_THAT(page.body(), HasSubstr("/three/build/three.module.min.js"));
  EXPECT_EQ(Request(http::verb::get, "/three/build/three.module.min.js").result(),
            http::status::ok);
  EXPECT_EQ(Request(http::verb::get, "/page.js").result(), http::status::ok);
  EXPECT_EQ(Request(http::verb::get, "/package.json").result(), http::status::not_found);
  EXPECT_EQ(Request(http::verb::get, "/three/../../web_server.cc").result(),
            http::status::not_found);
  EXPECT_EQ(Request(http::verb::post, "/").result(), http::status::method_not_allowed);
}

TEST_F(WebServerTest, MalformedAndOversizedRequestsAreRefused) {
  tcp::socket socket = Connect();
  asio::write(socket, asio::buffer(std::string("NOT HTTP AT ALL\r\n\r\n")));
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  beast::tcp_stream stream(std::move(socket));
  http::read(stream, buffer, response);
  EXPECT_EQ(response.result(), http::status::bad_request);
  const auto huge = Request(http::verb::get, "/" + std::string(10000, 'a'));
  EXPECT_EQ(huge.result(), http::status::bad_request);
}

TEST_F(WebServerTest, ALatePageGetsTheSceneAndTheNewestFrameAtOnce) {
  server_->SetScene(R"({"type":"scene","version":1})");
  server_->PublishFrame(R"({"type":"frame","n":1})");
  server_->PublishFrame(R"({"type":"frame","n":2})");
  auto page = Page();
  EXPECT_EQ(Read(*page), R"({"type":"scene","version":1})");
  EXPECT_EQ(Read(*page), R"({"type":"frame","n":2})");
}

// What the viewer's threads hand to the web thread (WebView: the newest pose, to encode and
// send) runs there, in the order posted, not on the poster's thread.
TEST_F(WebServerTest, PostedWorkRunsOnTheWebThreadInOrder) {
  std::mutex mutex;
  std::condition_variable ran;
  std::vector<std::pair<int, std::thread::id>> seen;  // each task's number and thread
  for (int i = 0; i < 3; ++i) {
    server_->Post([&, i] {
      std::lock_guard<std::mutex> lock(mutex);
      seen.emplace_back(i, std::this_thread::get_id());
      ran.notify_all();
    });
  }
  std::unique_lock<std::mutex> lock(mutex);
  ASSERT_TRUE(ran.wait_for(lock, std::chrono::seconds(30), [&] { return seen.size() == 3; }));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(seen[i].first, i);
    EXPECT_NE(seen[i].second, std::this_thread::get_id());
    EXPECT_EQ(seen[i].second, seen[0].second);
  }
}

TEST_F(WebServerTest, PagesPastTheLimitAreRefusedWithTheFlagNamed) {
  auto first = Page();
  auto second = Page();
  beast::tcp_stream third(Connect());  // the upgrade request a browser sends
  http::request<http::string_body> upgrade(http::verb::get, "/ws", 11);
  upgrade.set(http::field::host, "127.0.0.1");
  upgrade.set(http::field::connection, "Upgrade");
  upgrade.set(http::field::upgrade, "websocket");
  upgrade.set(http::field::sec_websocket_version, "13");
  upgrade.set(http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
  http::write(third, upgrade);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(third, buffer, response);
  EXPECT_EQ(response.result(), http::status::service_unavailable);
  EXPECT_THAT(response.body(), HasSubstr("--web-max-pages"));
}

// A page that never reads holds at most one frame; the other page gets every newest frame
// (a hang here is the failure). A real browser page stalled, with its missed count, the
// other page's pace and the probes checked, is WebViewTest's
// AStalledPageMissesFramesWhileTheOtherKeepsPaceAndProbesGoOn (tests/e2e).
TEST_F(WebServerTest, AStalledPageNeverSlowsAnother) {
  server_->SetScene(R"({"type":"scene"})");
  auto stalled = Page();  // never read from
  auto reader = Page();
  EXPECT_THAT(Read(*reader), HasSubstr("scene"));
  const std::string padding(64 * 1024, ' ');  // fills the stalled socket's buffers soon
  for (int n = 1; n <= 2000; ++n) {
    server_->PublishFrame(R"({"type":"frame","n":)" + std::to_string(n) + "}" + padding);
  }
  std::string last;
  int read = 0;
  while (last.find("\"n\":2000}") == std::string::npos) {
    last = Read(*reader);
    ++read;
  }
  // It reached the newest frame while the other page held its socket full, frames in order.
  EXPECT_LE(read, 2000);
  EXPECT_THAT(last, HasSubstr("\"n\":2000}"));
}

TEST_F(WebServerTest, AnOversizedMessageClosesThePage) {
  auto page = Page();
  page->write(asio::buffer(std::string(10000, 'x')));
  beast::flat_buffer buffer;
  beast::error_code ec;
  page->read(buffer, ec);
  EXPECT_TRUE(ec);
  page->next_layer().close();
  auto again = Page();  // the server still answers
  again->write(asio::buffer(std::string(R"({"pause":true})")));
  again->close(websocket::close_code::normal);
}

TEST(WebViewControls, ParsesThePagesControlsAndNothingElse) {
  v1::ReplayControl control;
  ASSERT_TRUE(WebView::ParseControl(R"({"pause":true})", &control));
  EXPECT_TRUE(control.pause());
  ASSERT_TRUE(WebView::ParseControl(R"({"seek_seq":42})", &control));
  EXPECT_EQ(control.seek_seq(), 42);
  ASSERT_TRUE(WebView::ParseControl(R"({"step":-1})", &control));
  EXPECT_EQ(control.step(), -1);
  ASSERT_TRUE(WebView::ParseControl(R"({"speed":2.5})", &control));
  EXPECT_DOUBLE_EQ(control.speed(), 2.5);
  for (const char* bad : {"", "[]", "{}", R"({"seek_seq":-1})", R"({"speed":1e9})", R"({"step":0})",
                          R"({"pause":true,"resume":true})", R"({"quit":1})", "not json"}) {
    EXPECT_FALSE(WebView::ParseControl(bad, &control)) << bad;
  }
}

// A self-signed certificate for 127.0.0.1, made by openssl (Debian's openssl) for this suite.
class WebServerTlsTest : public WebServerTest {
 protected:
  static void SetUpTestSuite() {
    dir_ =
        new std::filesystem::path(std::filesystem::temp_directory_path() /
                                  ("mbstream-web-tls-" + std::to_string(std::random_device()())));
    std::filesystem::create_directories(*dir_);
    const std::string command =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=127.0.0.1 "
        "-addext subjectAltName=IP:127.0.0.1 -keyout " +
        (*dir_ / "key.pem").string() + " -out " + (*dir_ / "cert.pem").string() +
        " > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << "openssl (Debian package openssl) failed";
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  void SetUp() override {
    WebOptions options;
    options.max_pages = 2;
    options.tls_cert_file = (*dir_ / "cert.pem").string();
    options.tls_key_file = (*dir_ / "key.pem").string();
    Restart(std::move(options));
    client_.load_verify_file((*dir_ / "cert.pem").string());  // the only certificate trusted
    client_.set_verify_mode(asio::ssl::verify_peer);
  }
  std::unique_ptr<beast::ssl_stream<tcp::socket>> Tls() {
    auto stream = std::make_unique<beast::ssl_stream<tcp::socket>>(Connect(), client_);
    stream->set_verify_callback(asio::ssl::host_name_verification("127.0.0.1"));
    stream->handshake(asio::ssl::stream_base::client);
    return stream;
  }

  static std::filesystem::path* dir_;
  asio::ssl::context client_{asio::ssl::context::tls_client};
};
std::filesystem::path* WebServerTlsTest::dir_ = nullptr;

TEST_F(WebServerTlsTest, ServesThePageOverHttpsAndTheSceneOverWss) {
  EXPECT_EQ(server_->url().rfind("https://127.0.0.1:", 0), 0u) << server_->url();
  auto https = Tls();  // verified against the certificate, for 127.0.0.1
  http::request<http::string_body> request(http::verb::get, "/", 11);
  request.set(http::field::host, "127.0.0.1");
  http::write(*https, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> page;
  http::read(*https, buffer, page);
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_THAT(page.body(), HasSubstr("/page.js"));

  server_->SetScene(R"({"type":"scene","version":7})");
  websocket::stream<beast::ssl_stream<tcp::socket>> wss(std::move(*Tls()));
  wss.handshake("127.0.0.1", "/ws");
  beast::flat_buffer message;
  wss.read(message);
  EXPECT_EQ(beast::buffers_to_string(message.data()), R"({"type":"scene","version":7})");
}

TEST_F(WebServerTlsTest, PlainHttpToTheTlsPortGetsNoPage) {
  tcp::socket socket = Connect();
  asio::write(socket, asio::buffer(std::string("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")));
  std::string answer(4096, '\0');
  beast::error_code ec;
  const std::size_t n = socket.read_some(asio::buffer(answer), ec);
  EXPECT_EQ(answer.substr(0, n).find("HTTP/1.1 200"), std::string::npos);
  auto https = Tls();  // and the server still answers
  SUCCEED();
}

// Pages checked as the viewer checks them with the simulation server (here a fake check):
// nothing before the token is admitted, a refused page is told why (401/403) and closed.
class WebServerAccessTest : public WebServerTest {
 protected:
  void SetUp() override {
    WebOptions options;
    options.max_pages = 4;
    options.check_access = [this](const std::string& token,
                                  std::function<void(WebOptions::Access)> done) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        checked_.push_back(token);
      }
      if (token == "good") return done({});
      if (token == "watch") return done({0, "it needs the run role", false});
      if (token.empty()) return done({401, "the simulation server requires a token"});
      return done({403, "this token may not watch runs"});
    };
    Restart(std::move(options));
    server_->SetScene(R"({"type":"scene","version":3})");
    server_->PublishFrame(R"({"type":"frame","n":1})");
  }
  std::vector<std::string> Checked() {
    std::lock_guard<std::mutex> lock(mutex_);
    return checked_;
  }
  std::mutex mutex_;  // the check runs on the server's thread
  std::vector<std::string> checked_;
};

TEST_F(WebServerAccessTest, AGoodTokenGetsTheSceneAndTheFrame) {
  auto page = Page();
  page->write(asio::buffer(std::string(R"({"token":"good"})")));
  EXPECT_EQ(Read(*page), R"({"controls":true,"message":"","type":"access"})");
  EXPECT_EQ(Read(*page), R"({"type":"scene","version":3})");
  EXPECT_EQ(Read(*page), R"({"type":"frame","n":1})");
  page->write(asio::buffer(std::string(R"({"pause":true})")));  // controls pass after it
  server_->PublishFrame(R"({"type":"frame","n":2})");
  EXPECT_EQ(Read(*page), R"({"type":"frame","n":2})");
  EXPECT_EQ(Checked(), std::vector<std::string>{"good"});
  EXPECT_EQ(Controls(1), std::vector<std::string>{R"({"pause":true})"});
}

// A page admitted to watch only: told so first; its controls are refused to it alone, never
// passed on, and it keeps getting frames.
TEST_F(WebServerAccessTest, AWatchOnlyPagesControlsAreRefusedAndItWatchesOn) {
  auto page = Page();
  page->write(asio::buffer(std::string(R"({"token":"watch"})")));
  EXPECT_EQ(Read(*page), R"({"controls":false,"message":"it needs the run role","type":"access"})");
  EXPECT_EQ(Read(*page), R"({"type":"scene","version":3})");
  EXPECT_EQ(Read(*page), R"({"type":"frame","n":1})");
  page->write(asio::buffer(std::string(R"({"seek_seq":5})")));
  EXPECT_EQ(Read(*page), R"({"message":"it needs the run role","type":"control_refused"})");
  auto good = Page();  // a page that may steer: its control is the first passed on
  good->write(asio::buffer(std::string(R"({"token":"good"})")));
  EXPECT_THAT(Read(*good), HasSubstr(R"("controls":true)"));
  good->write(asio::buffer(std::string(R"({"pause":true})")));
  EXPECT_EQ(Controls(1), std::vector<std::string>{R"({"pause":true})"});
  server_->PublishFrame(R"({"type":"frame","n":2})");
  EXPECT_EQ(Read(*page), R"({"type":"frame","n":2})");
}

TEST_F(WebServerAccessTest, AWrongOrMissingTokenIsRefusedWithItsStatusAndClosed) {
  for (const auto& [token, status] :
       std::vector<std::pair<std::string, int>>{{"stolen", 403}, {"", 401}}) {
    auto page = Page();
    page->write(asio::buffer(std::string(R"({"pause":true})")));  // before the token: ignored
    page->write(asio::buffer(R"({"token":")" + token + R"("})"));
    const std::string denied = Read(*page);
    EXPECT_THAT(denied, HasSubstr(R"("type":"denied")")) << token;
    EXPECT_THAT(denied, HasSubstr(R"("status":)" + std::to_string(status))) << token;
    EXPECT_THAT(denied, ::testing::Not(HasSubstr("scene")));
    beast::flat_buffer buffer;
    beast::error_code ec;
    page->read(buffer, ec);  // the close the viewer sent
    EXPECT_EQ(ec, websocket::error::closed) << token << ": " << ec.message();
    EXPECT_EQ(page->reason().code, websocket::close_code::policy_error) << token;
  }
  EXPECT_TRUE(Controls(0).empty());  // (the refused pages' controls came before their tokens)
}

}  // namespace
}  // namespace mbstream::viewer
