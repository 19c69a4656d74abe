// The --web server on its own (no viewer, no browser): the page's files and nothing else,
// refusals of malformed and unexpected requests, the snapshot on connect, the page limit,
// a stalled page that never slows another, and the page's replay controls.
#include <gmock/gmock.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <string>

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
    server_ = std::make_unique<WebServer>(WebOptions{"127.0.0.1:0", MBSTREAM_WEB_ROOT, 2},
                                          [this](const std::string& json) {
                                            controls_.push_back(json);
                                            return true;
                                          });
    server_->Start();
    const std::string url = server_->url();
    port_ = url.substr(url.rfind(':') + 1, url.size() - url.rfind(':') - 2);
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

  asio::io_context ioc_;
  std::unique_ptr<WebServer> server_;
  std::string port_;
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

// A page that never reads holds at most one frame; the other page gets every newest frame.
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
  while (last.find("\"n\":2000}") == std::string::npos) last = Read(*reader);
  SUCCEED();  // reached the newest frame while the other page held its socket full
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

}  // namespace
}  // namespace mbstream::viewer
