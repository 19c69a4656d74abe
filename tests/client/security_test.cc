// TLS, client certificates, tokens with roles and owner-only unix sockets, with real
// processes. Certificates are made by the test with openssl (never committed keys).
#include <gmock/gmock.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr char kAdminToken[] = "admin-token-0123456789abcdef";
constexpr char kViewToken[] = "view-token-0123456789abcdef";

std::string ReadFile(const fs::path& path) { return ReadTextFile(path.string()); }

class SecurityTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::random_device random;
    dir_ = new fs::path(fs::temp_directory_path() / ("mbstream-sec-" + std::to_string(random())));
    fs::create_directories(*dir_);
    const std::string d = dir_->string();
    // A CA, a server certificate for 127.0.0.1/localhost, a client certificate, another CA.
    const std::string script =
        "cd " + d +
        " && set -e && "
        "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=test-ca -keyout ca.key "
        "-out ca.pem && "
        "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=other-ca -keyout other.key "
        "-out other.pem && "
        "openssl req -newkey rsa:2048 -nodes -subj /CN=localhost -keyout server.key -out "
        "server.csr && "
        "printf 'subjectAltName=IP:127.0.0.1,DNS:localhost' > san.ext && "
        "openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 "
        "-extfile san.ext -out server.pem && "
        "openssl req -newkey rsa:2048 -nodes -subj /CN=client -keyout client.key -out "
        "client.csr && "
        "openssl x509 -req -in client.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 "
        "-out client.pem";
    const CommandOutcome made = RunCommand(script);
    ASSERT_EQ(made.exit_code, 0) << made.output;
    std::ofstream(*dir_ / "tokens") << "# test tokens\n"
                                    << kAdminToken << " admin\n"
                                    << kViewToken << " view\n";
    std::ofstream(*dir_ / "admin.token") << kAdminToken << "\n";
    std::ofstream(*dir_ / "view.token") << kViewToken << "\n";
    std::ofstream(*dir_ / "bad.token") << "not-a-known-token-at-all\n";
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  void TearDown() override { server_.reset(); }

  static std::string F(const std::string& name) { return (*dir_ / name).string(); }
  void StartServer(const std::vector<std::string>& args,
                   const std::string& listen = "127.0.0.1:0") {
    fs::remove_all(*dir_ / "data");
    server_ = std::make_unique<ServerProcess>(MBSTREAM_SERVER, F("data"), args, listen);
  }
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }

  static fs::path* dir_;
  std::unique_ptr<ServerProcess> server_;
};

fs::path* SecurityTest::dir_ = nullptr;

TEST_F(SecurityTest, TokensAndRoles) {
  StartServer({"--token-file", F("tokens")});
  CommandOutcome outcome = Cli("models");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("needs a token"));

  outcome = Cli("--token-file " + F("bad.token") + " models");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("not known"));

  outcome = Cli("--token-file " + F("view.token") + " models");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  outcome = Cli("--token-file " + F("view.token") + " submit models/irb1600");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("lacks the role 'submit'"));
  outcome = Cli("--token-file " + F("view.token") + " run irb1600");
  EXPECT_THAT(outcome.output, HasSubstr("lacks the role 'run'"));

  outcome = Cli("--token-file " + F("admin.token") + " run irb1600 --spec " +
                "models/irb1600/seed-run.json --out " + F("out-token"));
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  server_->Stop();
  const std::string log = ReadFile(server_->log_path());
  EXPECT_THAT(log, Not(HasSubstr(kAdminToken)));
  EXPECT_THAT(log, Not(HasSubstr(kViewToken)));
  EXPECT_THAT(log, Not(HasSubstr("not-a-known-token")));
}

TEST_F(SecurityTest, TlsWithTokenRunsEndToEndAndTheWrongCaIsRejected) {
  StartServer(
      {"--tls-cert", F("server.pem"), "--tls-key", F("server.key"), "--token-file", F("tokens")});
  CommandOutcome outcome =
      Cli("--ca " + F("ca.pem") + " --token-file " + F("admin.token") +
          " run irb1600 --spec models/irb1600/seed-run.json --watch --out " + F("out-tls"));
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_TRUE(fs::exists(*dir_ / "out-tls" / "tcp.csv"));

  outcome = Cli("--ca " + F("other.pem") + " --token-file " + F("admin.token") + " models");
  EXPECT_NE(outcome.exit_code, 0);
  outcome = Cli("--token-file " + F("admin.token") + " models");  // plaintext to a TLS server
  EXPECT_NE(outcome.exit_code, 0);
}

TEST_F(SecurityTest, ClientCertificatesAreRequiredWhenConfigured) {
  StartServer({"--tls-cert", F("server.pem"), "--tls-key", F("server.key"), "--tls-client-ca",
               F("ca.pem")});
  EXPECT_NE(Cli("--ca " + F("ca.pem") + " models").exit_code, 0);
  const CommandOutcome outcome = Cli("--ca " + F("ca.pem") + " --tls-cert " + F("client.pem") +
                                     " --tls-key " + F("client.key") + " models");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_THAT(outcome.output, HasSubstr("irb1600"));
}

TEST_F(SecurityTest, TokenIsNotSentInTheClearToARemoteAddress) {
  const CommandOutcome outcome =
      RunCommand(std::string(MBSTREAM_CLI) + " --server 192.0.2.1:50051 --token-file " +
                 F("admin.token") + " models");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("refusing to send a token in the clear"));
}

TEST_F(SecurityTest, UnixSocketIsOwnerOnly) {
  const std::string socket = F("mbstream.sock");
  StartServer({}, "unix:" + socket);
  struct stat info {};
  ASSERT_EQ(stat(socket.c_str(), &info), 0);
  EXPECT_TRUE(S_ISSOCK(info.st_mode));
  EXPECT_EQ(info.st_mode & 077, 0u)
      << "group/other may use the socket: " << std::oct << (info.st_mode & 0777);
  const CommandOutcome outcome = Cli("models");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
}

TEST_F(SecurityTest, MalformedTokenFileIsNamedWithItsLine) {
  std::ofstream(*dir_ / "bad-tokens") << "short admin\n";
  const CommandOutcome outcome =
      RunCommand(std::string(MBSTREAM_SERVER) + " --listen 127.0.0.1:0 --data " + F("data-bad") +
                 " --token-file " + F("bad-tokens"));
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("bad-tokens:1: the token is shorter than 16"));
}

}  // namespace
}  // namespace mbstream::testing
