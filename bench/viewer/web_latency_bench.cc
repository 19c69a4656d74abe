// The --web stream's latency against issue 30's targets (p50 <= 2 ms, p99 <= 20 ms with 10
// pages at 20 Hz on loopback): the viewer's WebServer on 127.0.0.1:0 and N pages in this
// process (Beast WebSocket clients, one thread each, reading as a browser's socket does),
// frames published at a fixed rate as the viewer's link publishes them (FrameMessageJson of
// the IRB 1600's 8 frames and one probe). Latency: from the publish call (the viewer has
// posed the frame) to a page having read the message. No browser: the page's drawing is not
// in it (docs/performance.md has the browser's figures from WebViewTest).
//
//   web_latency_bench [--pages 10] [--hz 20] [--seconds 20] [--stalled 0]
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "viewer/web/frame_message.h"
#include "viewer/web/web_server.h"

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using namespace mbstream::viewer;

double UnixMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

double NumberAfter(const std::string& text, const char* key) {
  const std::size_t at = text.find(key);
  return at == std::string::npos ? -1.0
                                 : std::strtod(text.c_str() + at + std::strlen(key), nullptr);
}

struct PageResult {
  std::vector<double> latency_ms;
  long long missed = 0;
};

// One page: reads until frame `last`, counting the frames it did not get.
void ReadPage(const std::string& port, long long last, PageResult* result) {
  asio::io_context ioc;
  tcp::resolver resolver(ioc);
  websocket::stream<tcp::socket> ws(ioc);
  asio::connect(ws.next_layer(), resolver.resolve("127.0.0.1", port));
  ws.next_layer().set_option(tcp::no_delay(true));
  ws.handshake("127.0.0.1", "/ws");
  long long previous = 0;
  beast::flat_buffer buffer;
  for (;;) {
    ws.read(buffer);
    const std::string text = beast::buffers_to_string(buffer.data());
    const double received = UnixMs();
    buffer.consume(buffer.size());
    if (text.find("\"type\":\"frame\"") == std::string::npos) continue;
    const auto n = static_cast<long long>(NumberAfter(text, "\"n\":"));
    result->latency_ms.push_back(received - NumberAfter(text, "\"posed_ms\":"));
    if (previous && n > previous + 1) result->missed += n - previous - 1;
    previous = n;
    if (n >= last) break;
  }
  beast::error_code ignored;
  ws.close(websocket::close_code::normal, ignored);
}

}  // namespace

int main(int argc, char** argv) {
  int pages = 10, stalled = 0;
  double hz = 20, seconds = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--pages")
      pages = std::atoi(argv[i + 1]);
    else if (flag == "--stalled")
      stalled = std::atoi(argv[i + 1]);
    else if (flag == "--hz")
      hz = std::atof(argv[i + 1]);
    else if (flag == "--seconds")
      seconds = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr,
                   "usage: web_latency_bench [--pages N] [--hz X] [--seconds S] [--stalled N]\n");
      return 2;
    }
  }
  const long long frames = std::max(1LL, static_cast<long long>(hz * seconds));
  WebOptions options;
  options.address = "127.0.0.1:0";
  options.root = MBSTREAM_WEB_ROOT;
  options.max_pages = pages + stalled + 1;
  WebServer server(std::move(options), nullptr);
  server.Start();
  const std::string url = server.url();
  const std::string port = url.substr(url.rfind(':') + 1, url.size() - url.rfind(':') - 2);
  server.SetScene(R"({"type":"scene","version":1})");

  std::vector<PageResult> results(static_cast<std::size_t>(pages));
  std::vector<std::thread> readers;
  for (int p = 0; p < pages; ++p) readers.emplace_back(ReadPage, port, frames, &results[p]);
  asio::io_context stalled_ioc;  // pages that open and never read
  std::vector<std::unique_ptr<websocket::stream<tcp::socket>>> stalled_pages;
  for (int p = 0; p < stalled; ++p) {
    auto ws = std::make_unique<websocket::stream<tcp::socket>>(stalled_ioc);
    tcp::resolver resolver(stalled_ioc);
    asio::connect(ws->next_layer(), resolver.resolve("127.0.0.1", port));
    ws->handshake("127.0.0.1", "/ws");
    stalled_pages.push_back(std::move(ws));
  }
  while (server.pages() < pages + stalled)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));

  // The viewer's frame: the IRB 1600's 8 frame matrices and its TCP probe.
  std::vector<Eigen::Isometry3d> poses(8, Eigen::Isometry3d::Identity());
  std::vector<ProbeReport> probes{{"Tcp", Eigen::Vector3d(0.9, 0.1, 1.2), "World"}};
  mbstream::v1::ViewerStatus status;
  status.set_run_id("r-20261126-230000-bench");
  status.set_state("running");
  status.set_mode("live");
  std::size_t bytes = 0;
  const auto period = std::chrono::duration<double>(1.0 / hz);
  const auto start = std::chrono::steady_clock::now();
  for (long long n = 1; n <= frames; ++n) {
    std::this_thread::sleep_until(
        start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(period * n));
    for (auto& pose : poses) pose.rotate(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()));
    status.set_seq(n);
    status.set_t_s(static_cast<double>(n) / hz);
    FrameMessage frame;
    frame.scene_version = 1;
    frame.number = static_cast<std::uint64_t>(n);
    frame.posed_unix_ms = UnixMs();
    frame.frames = poses;
    frame.probes = probes;
    std::string json = FrameMessageJson(frame, status);
    bytes = json.size();
    server.PublishFrame(std::move(json));
  }
  for (auto& reader : readers) reader.join();
  server.Stop();

  std::vector<double> all;
  long long missed = 0;
  for (const auto& r : results) {
    all.insert(all.end(), r.latency_ms.begin(), r.latency_ms.end());
    missed += r.missed;
  }
  std::sort(all.begin(), all.end());
  const auto at = [&](double q) {
    return all.empty() ? -1.0
                       : all[static_cast<std::size_t>(q * static_cast<double>(all.size() - 1))];
  };
  std::printf(
      "web_latency_bench: %d pages (+%d stalled) at %.0f Hz for %.0f s, %zu bytes/frame: "
      "posed -> read p50 %.3f ms, p90 %.3f ms, p99 %.3f ms, max %.3f ms over %zu frames read; "
      "%lld missed; targets p50 <= 2 ms, p99 <= 20 ms: %s\n",
      pages, stalled, hz, seconds, bytes, at(0.5), at(0.9), at(0.99),
      all.empty() ? -1.0 : all.back(), all.size(), missed,
      at(0.5) <= 2.0 && at(0.99) <= 20.0 ? "met" : "MISSED");
  return 0;
}
