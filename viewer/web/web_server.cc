#include "viewer/web/web_server.h"

#include <spdlog/spdlog.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <type_traits>

namespace mbstream::viewer {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

constexpr std::size_t kMaxRequestBytes = 8 * 1024;
constexpr std::size_t kMaxMessageBytes = 4 * 1024;
constexpr auto kHttpTimeout = std::chrono::seconds(30);
constexpr auto kTokenTimeout = std::chrono::seconds(10);  // from a page's open to its token
// A page's socket send buffer (the kernel doubles it): what a stalled page can still have
// queued behind the newest frame, about 90 frames of 1.4 KB, instead of the megabytes
// Linux's autotuning grows to on a fast link (a page woken from a stall would otherwise get
// a minute of old frames before the newest).
constexpr int kPageSendBufferBytes = 64 * 1024;

// URL path -> file under the root; empty when the path is not one of the page's files.
std::filesystem::path FileFor(const std::filesystem::path& root, std::string_view target) {
  const std::string_view path = target.substr(0, target.find_first_of("?#"));
  if (path == "/" || path == "/index.html") return root / "index.html";
  if (path.find("..") != std::string_view::npos || path.find('\\') != std::string_view::npos) {
    return {};
  }
  if (path == "/page.js" || path == "/page.css") return root / path.substr(1);
  constexpr std::string_view kThree = "/three/";  // three.js as npm installed it
  if (path.rfind(kThree, 0) == 0) {
    return root / "node_modules" / "three" / path.substr(kThree.size());
  }
  return {};
}

const char* MimeType(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  return "application/octet-stream";
}

std::string Endpoint(const tcp::socket& socket) {
  beast::error_code ec;
  const tcp::endpoint remote = socket.remote_endpoint(ec);
  if (ec) return "?";
  return remote.address().to_string() + ":" + std::to_string(remote.port());
}

}  // namespace

struct WebServer::Impl : std::enable_shared_from_this<WebServer::Impl> {
  // One page's WebSocket, plain or TLS (PageSession below).
  class Page {
   public:
    virtual ~Page() = default;
    // Any thread: a message to send (the scene replaces everything waiting).
    virtual void Send(std::shared_ptr<const std::string> message, bool is_scene) = 0;
  };

  WebOptions options;
  OnControl on_control;
  asio::io_context ioc{1};
  std::optional<asio::ssl::context> tls;  // with --web-tls
  tcp::acceptor acceptor{ioc};
  std::thread thread;
  std::atomic<int> pages{0};

  std::mutex mutex;  // guards the fields below
  std::set<std::shared_ptr<Page>> open;
  std::shared_ptr<const std::string> scene, frame;

  void Accept();
  void Publish(std::shared_ptr<const std::string> message, bool is_scene);
};

namespace {

using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// The token message a page sends first when pages are checked: {"token":"..."}.
std::optional<std::string> TokenIn(const std::string& text) {
  const nlohmann::json message = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!message.is_object() || message.size() != 1 || !message.contains("token") ||
      !message["token"].is_string()) {
    return std::nullopt;
  }
  return message["token"].get<std::string>();
}

// One page's WebSocket: (when pages are checked) its token, then the scene, then the newest
// frame, never a queue.
template <class Stream>
class PageSession : public WebServer::Impl::Page,
                    public std::enable_shared_from_this<PageSession<Stream>> {
 public:
  PageSession(std::shared_ptr<WebServer::Impl> server, Stream stream, std::string peer)
      : server_(std::move(server)),
        ws_(std::move(stream)),
        peer_(std::move(peer)),
        token_timer_(ws_.get_executor()) {}

  void Open(http::request<http::string_body> request) {
    beast::error_code ignored;  // frames are small: no Nagle delay behind a delayed ACK
    beast::get_lowest_layer(ws_).socket().set_option(tcp::no_delay(true), ignored);
    beast::get_lowest_layer(ws_).socket().set_option(
        asio::socket_base::send_buffer_size(kPageSendBufferBytes), ignored);
    beast::get_lowest_layer(ws_).expires_never();  // the WebSocket's own timeouts from here
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxMessageBytes);
    ws_.async_accept(request, beast::bind_front_handler(&PageSession::OnOpen, Self()));
  }

  void Send(std::shared_ptr<const std::string> message, bool is_scene) override {
    asio::post(ws_.get_executor(), [self = Self(), message, is_scene] {
      if (is_scene) {
        self->scene_ = message;
        self->frame_.reset();
      } else {
        self->frame_ = message;
      }
      self->Write();
    });
  }

 private:
  std::shared_ptr<PageSession> Self() { return this->shared_from_this(); }

  void OnOpen(beast::error_code ec) {
    if (ec) {
      spdlog::warn("web: page {}: WebSocket handshake failed: {}", peer_, ec.message());
      return Closed();
    }
    if (!server_->options.check_access) {
      Admit({});
    } else {
      token_timer_.expires_after(kTokenTimeout);
      token_timer_.async_wait([self = Self()](beast::error_code timer_ec) {
        if (timer_ec || self->admitted_ || self->checking_ || self->closed_) return;
        self->Deny({401, "no token message within " + std::to_string(kTokenTimeout.count()) +
                             " s of opening"});
      });
    }
    Read();
  }

  // The page may have what the other pages have: it joins them, with the snapshot.
  void Admit(const WebOptions::Access& access) {
    admitted_ = true;
    controls_ = access.controls;
    controls_message_ = access.message;
    if (server_->options.check_access) {  // what the page may do, before the scene
      notice_ = std::make_shared<const std::string>(nlohmann::json{
          {"type", "access"},
          {"controls", access.controls},
          {"message", access.message}}.dump());
    }
    std::shared_ptr<const std::string> scene, frame;
    {
      std::lock_guard<std::mutex> lock(server_->mutex);
      server_->open.insert(Self());
      scene = server_->scene;
      frame = server_->frame;
    }
    spdlog::info("web: page {} opened ({} open)", peer_, server_->pages.load());
    if (scene) scene_ = scene;  // the snapshot: what the other pages show now
    if (frame) frame_ = frame;
    Write();
  }

  void OnToken(const std::string& token) {
    checking_ = true;
    token_timer_.cancel();
    server_->options.check_access(token, [self = Self()](WebOptions::Access access) {
      asio::post(self->ws_.get_executor(), [self, access] {
        self->checking_ = false;
        if (self->closed_) return;
        if (access.status != 0) return self->Deny(access);
        self->Admit(access);
      });
    });
  }

  // Tells the page why, then closes (1008: policy); the page asks for a token on 401/403.
  void Deny(const WebOptions::Access& access) {
    spdlog::warn("web: page {} refused ({}): {}", peer_, access.status, access.message);
    denied_ = std::make_shared<const std::string>(nlohmann::json{
        {"type", "denied"},
        {"status", access.status},
        {"message", access.message}}.dump());
    scene_.reset();
    frame_.reset();
    notice_.reset();
    if (!writing_) Write();
  }

  void Write() {
    if (writing_ || closed_) return;
    if (denied_) {
      writing_ = true;
      ws_.text(true);
      ws_.async_write(asio::buffer(*denied_), [self = Self()](beast::error_code ec, std::size_t) {
        if (ec) return self->Closed();
        self->ws_.async_close(
            websocket::close_reason(websocket::close_code::policy_error, "access denied"),
            [self](beast::error_code) { self->Closed(); });
      });
      return;
    }
    if (!admitted_) return;
    std::shared_ptr<const std::string>& slot = notice_ ? notice_ : scene_ ? scene_ : frame_;
    std::shared_ptr<const std::string> next = std::move(slot);
    if (!next) return;
    writing_ = true;
    sending_ = next;
    ws_.text(true);
    ws_.async_write(asio::buffer(*sending_), [self = Self()](beast::error_code ec, std::size_t) {
      self->writing_ = false;
      self->sending_.reset();
      if (ec) {
        spdlog::info("web: page {} closed while sending: {}", self->peer_, ec.message());
        return self->Closed();
      }
      self->Write();
    });
  }

  void Read() {
    ws_.async_read(buffer_, [self = Self()](beast::error_code ec, std::size_t) {
      if (ec) {
        if (ec == websocket::error::message_too_big) {
          spdlog::warn("web: page {} sent a message over {} bytes: closed", self->peer_,
                       kMaxMessageBytes);
        } else if (ec != websocket::error::closed && ec != asio::error::operation_aborted) {
          spdlog::info("web: page {} closed: {}", self->peer_, ec.message());
        } else {
          spdlog::info("web: page {} closed", self->peer_);
        }
        return self->Closed();
      }
      const std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      self->OnMessage(text);
      self->Read();
    });
  }

  void OnMessage(const std::string& text) {
    const std::optional<std::string> token = ws_.got_text() ? TokenIn(text) : std::nullopt;
    if (!server_->options.check_access) {
      if (token) return;  // pages are not checked: the token is not needed
    } else if (!admitted_) {
      if (token && !checking_ && !denied_) return OnToken(*token);
      spdlog::warn("web: page {}: a message before its token was checked: ignored", peer_);
      return;
    }
    if (token) return;  // a page that sent its token again (reconnect logic): nothing to do
    if (!controls_) {   // it watches only: the replay is every page's and the window's
      spdlog::warn("web: page {}: control refused: {}", peer_, controls_message_);
      notice_ = std::make_shared<const std::string>(
          nlohmann::json{{"type", "control_refused"}, {"message", controls_message_}}.dump());
      return Write();
    }
    if (!ws_.got_text() || !server_->on_control || !server_->on_control(text)) {
      spdlog::warn("web: page {}: control '{}' not applied", peer_, text.substr(0, 200));
    }
  }

  void Closed() {
    if (closed_) return;
    closed_ = true;
    token_timer_.cancel();
    --server_->pages;
    std::lock_guard<std::mutex> lock(server_->mutex);
    server_->open.erase(Self());
  }

  std::shared_ptr<WebServer::Impl> server_;
  websocket::stream<Stream> ws_;
  std::string peer_;
  asio::steady_timer token_timer_;
  beast::flat_buffer buffer_;
  std::shared_ptr<const std::string> scene_, frame_, sending_, denied_;
  std::shared_ptr<const std::string> notice_;  // to this page alone, before the scene
  bool admitted_ = false;                      // may get the scene and frames
  bool controls_ = true;                       // may steer the replay
  std::string controls_message_;
  bool checking_ = false;  // its token is being checked
  bool writing_ = false;
  bool closed_ = false;
};

// One HTTP connection (after the TLS handshake with --web-tls): files, or the upgrade to a
// page's WebSocket.
template <class Stream>
class HttpConnection : public std::enable_shared_from_this<HttpConnection<Stream>> {
 public:
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

  HttpConnection(std::shared_ptr<WebServer::Impl> server, Stream stream, std::string peer)
      : server_(std::move(server)), stream_(std::move(stream)), peer_(std::move(peer)) {}

  void Start() {
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(kHttpTimeout);
      stream_.async_handshake(
          asio::ssl::stream_base::server, [self = Self()](beast::error_code ec) {
            if (ec) {
              spdlog::warn("web: {}: TLS handshake failed: {}", self->peer_, ec.message());
              return;
            }
            self->Read();
          });
    } else {
      Read();
    }
  }

 private:
  std::shared_ptr<HttpConnection> Self() { return this->shared_from_this(); }

  void Read() {
    parser_.emplace();
    parser_->header_limit(kMaxRequestBytes);
    parser_->body_limit(kMaxRequestBytes);
    beast::get_lowest_layer(stream_).expires_after(kHttpTimeout);
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpConnection::OnRead, Self()));
  }

  void OnRead(beast::error_code ec, std::size_t) {
    if (ec == http::error::end_of_stream) return Shut();
    if (ec) {
      if (ec != beast::error::timeout && ec != asio::error::operation_aborted) {
        spdlog::warn("web: {}: bad request: {}", peer_, ec.message());
        return Reply(http::status::bad_request, "bad request: " + ec.message() + "\n", false);
      }
      spdlog::info("web: {}: {}", peer_, ec.message());
      return Shut();
    }
    http::request<http::string_body> request = parser_->release();
    if (websocket::is_upgrade(request)) {
      if (request.target() != "/ws") {
        return Reply(http::status::not_found, "the page's WebSocket is /ws\n", false);
      }
      if (server_->pages.fetch_add(1) >= server_->options.max_pages) {
        --server_->pages;
        spdlog::warn("web: {}: refused, {} pages open already (--web-max-pages)", peer_,
                     server_->options.max_pages);
        return Reply(http::status::service_unavailable,
                     "too many pages open (" + std::to_string(server_->options.max_pages) +
                         ", mbstream-viewer --web-max-pages)\n",
                     false);
      }
      auto page = std::make_shared<PageSession<Stream>>(server_, std::move(stream_), peer_);
      page->Open(std::move(request));
      return;
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      return Reply(http::status::method_not_allowed, "GET or HEAD only\n", request.keep_alive());
    }
    const std::string target(request.target());
    const std::filesystem::path file = FileFor(server_->options.root, target);
    std::ifstream in(file, std::ios::binary);
    if (file.empty() || !in) {
      return Reply(http::status::not_found, "not found: " + target.substr(0, 200) + "\n",
                   request.keep_alive());
    }
    std::ostringstream body;
    body << in.rdbuf();
    auto response =
        std::make_shared<http::response<http::string_body>>(http::status::ok, request.version());
    response->set(http::field::content_type, MimeType(file));
    response->set(http::field::cache_control, "no-cache");
    response->keep_alive(request.keep_alive());
    response->body() = request.method() == http::verb::head ? "" : body.str();
    response->content_length(body.str().size());
    Send(response);
  }

  void Reply(http::status status, std::string text, bool keep_alive) {
    auto response = std::make_shared<http::response<http::string_body>>(status, 11);
    response->set(http::field::content_type, "text/plain; charset=utf-8");
    response->keep_alive(keep_alive);
    response->body() = std::move(text);
    response->prepare_payload();
    Send(response);
  }

  void Send(std::shared_ptr<http::response<http::string_body>> response) {
    beast::get_lowest_layer(stream_).expires_after(kHttpTimeout);
    http::async_write(stream_, *response,
                      [self = Self(), response](beast::error_code ec, std::size_t) {
                        if (ec) return self->Shut();
                        if (!response->keep_alive()) return self->Shut();
                        self->Read();
                      });
  }

  void Shut() {
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(kHttpTimeout);
      stream_.async_shutdown([self = Self()](beast::error_code) {});
    } else {
      beast::error_code ignored;
      stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    }
  }

  std::shared_ptr<WebServer::Impl> server_;
  Stream stream_;
  std::string peer_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

void WebServer::Impl::Accept() {
  acceptor.async_accept(asio::make_strand(ioc),
                        [self = shared_from_this()](beast::error_code ec, tcp::socket socket) {
                          if (ec == asio::error::operation_aborted) return;
                          if (ec) {
                            spdlog::warn("web: accept: {}", ec.message());
                          } else {
                            std::string peer = Endpoint(socket);
                            if (self->tls) {
                              std::make_shared<HttpConnection<TlsStream>>(
                                  self, TlsStream(std::move(socket), *self->tls), std::move(peer))
                                  ->Start();
                            } else {
                              std::make_shared<HttpConnection<PlainStream>>(
                                  self, PlainStream(std::move(socket)), std::move(peer))
                                  ->Start();
                            }
                          }
                          self->Accept();
                        });
}

void WebServer::Impl::Publish(std::shared_ptr<const std::string> message, bool is_scene) {
  std::set<std::shared_ptr<Page>> pages_now;
  {
    std::lock_guard<std::mutex> lock(mutex);
    (is_scene ? scene : frame) = message;
    if (is_scene) frame.reset();
    pages_now = open;
  }
  for (const auto& page : pages_now) page->Send(message, is_scene);
}

WebServer::WebServer(WebOptions options, OnControl on_control) : impl_(std::make_shared<Impl>()) {
  impl_->options = std::move(options);
  impl_->on_control = std::move(on_control);
  if (!std::filesystem::exists(impl_->options.root / "index.html") ||
      !std::filesystem::exists(impl_->options.root / "node_modules/three/build/three.module.js")) {
    throw std::runtime_error("the web page's files are not in " + impl_->options.root.string() +
                             " (index.html, and three.js from 'npm ci' there: run "
                             "scripts/setup.sh, or give --web-root DIR)");
  }
  const WebOptions& o = impl_->options;
  if (!o.tls_cert_file.empty() || !o.tls_key_file.empty()) {
    if (o.tls_cert_file.empty() || o.tls_key_file.empty()) {
      throw std::runtime_error("--web-tls needs both files: CERT,KEY (PEM)");
    }
    asio::ssl::context& tls = impl_->tls.emplace(asio::ssl::context::tls_server);
    tls.set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                    asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                    asio::ssl::context::no_tlsv1_1);
    beast::error_code tls_ec;
    tls.use_certificate_chain_file(o.tls_cert_file, tls_ec);
    if (tls_ec) {
      throw std::runtime_error("--web-tls: cannot use the certificate " + o.tls_cert_file + ": " +
                               tls_ec.message() + " (a PEM certificate chain)");
    }
    tls.use_private_key_file(o.tls_key_file, asio::ssl::context::pem, tls_ec);
    if (tls_ec) {
      throw std::runtime_error("--web-tls: cannot use the key " + o.tls_key_file + ": " +
                               tls_ec.message() + " (the certificate's PEM private key)");
    }
  }
  const std::string& address = impl_->options.address;
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    throw std::runtime_error("--web '" + address + "' is not HOST:PORT, e.g. 127.0.0.1:8080");
  }
  std::string host = address.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  const std::string port = address.substr(colon + 1);
  beast::error_code ec;
  tcp::resolver resolver(impl_->ioc);
  const auto endpoints = resolver.resolve(host, port, tcp::resolver::passive, ec);
  if (ec || endpoints.empty()) {
    throw std::runtime_error("--web " + address + ": cannot resolve: " + ec.message());
  }
  const tcp::endpoint endpoint = *endpoints.begin();
  tcp::acceptor& acceptor = impl_->acceptor;
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("--web " + address + ": cannot listen: " + ec.message());
  if (!impl_->tls && !endpoint.address().is_loopback()) {
    spdlog::warn(
        "web: serving {} without --web-tls: the pages' tokens and the run cross the network in "
        "the clear; give --web-tls CERT,KEY (deploy/make-secrets.sh writes one)",
        address);
  }
}

WebServer::~WebServer() { Stop(); }

std::string WebServer::url() const {
  const tcp::endpoint local = impl_->acceptor.local_endpoint();
  std::string host = local.address().to_string();
  if (local.address().is_v6()) host = "[" + host + "]";
  return std::string(impl_->tls ? "https://" : "http://") + host + ":" +
         std::to_string(local.port()) + "/";
}

void WebServer::Start() {
  impl_->Accept();
  impl_->thread = std::thread([impl = impl_] { impl->ioc.run(); });
}

void WebServer::Stop() {
  if (!impl_->thread.joinable()) return;
  impl_->ioc.stop();  // the pages' sockets close with the handlers the io_context drops
  impl_->thread.join();
  beast::error_code ignored;
  impl_->acceptor.close(ignored);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->open.clear();  // (each page holds the server)
}

void WebServer::SetScene(std::string json) {
  impl_->Publish(std::make_shared<const std::string>(std::move(json)), true);
}

void WebServer::PublishFrame(std::string json) {
  impl_->Publish(std::make_shared<const std::string>(std::move(json)), false);
}

void WebServer::Post(std::function<void()> task) { asio::post(impl_->ioc, std::move(task)); }

int WebServer::pages() const { return impl_->pages.load(); }

}  // namespace mbstream::viewer
