// The server as a client sees it: statuses, documents, keep-alive, limits,
// and hostile clients (garbage, oversized, slow, half-open, too many).
#include <future>
#include <random>
#include <vector>

#include "server_fixture.hpp"

namespace mtc::bridge::test {
namespace {

TEST_F(ServerTest, CurrentAnswersXmlWithLengthAndDate) {
  agent_->add("door", "OPEN");
  const auto response = get("/current");
  EXPECT_EQ(response.status, 200);
  EXPECT_EQ(response.header("content-type"), "text/xml");
  EXPECT_EQ(response.header("content-length"), std::to_string(response.body.size()));
  EXPECT_FALSE(response.header("date").empty());
  const auto doc = parse_xml(response.body);
  EXPECT_STREQ(doc.select_node("//Event[@dataItemId='door']").node().text().get(), "OPEN");
}

TEST_F(ServerTest, KeepAliveServesManyRequestsOnOneConnection) {
  RawClient client(port());
  for (int i = 0; i < 20; ++i) {
    agent_->add("count", std::to_string(i));
    client.send(get_request("/current"));
    const auto response = client.read_response();
    ASSERT_TRUE(response) << "request " << i;
    EXPECT_EQ(response->status, 200);
    EXPECT_TRUE(response->header("connection").empty());  // persistent by default
    const auto doc = parse_xml(response->body);
    EXPECT_EQ(std::string(doc.select_node("//Event[@dataItemId='count']").node().text().get()),
              std::to_string(i));
  }
  EXPECT_FALSE(client.eof());
}

TEST_F(ServerTest, PipelinedRequestsAreAnsweredInOrder) {
  RawClient client(port());
  client.send(get_request("/probe") + get_request("/nowhere") + get_request("/current"));
  const auto first = client.read_response();
  const auto second = client.read_response();
  const auto third = client.read_response();
  ASSERT_TRUE(first && second && third);
  EXPECT_EQ(first->status, 200);
  EXPECT_NE(first->body.find("MTConnectDevices"), std::string::npos);
  EXPECT_EQ(second->status, 404);
  EXPECT_EQ(third->status, 200);
}

TEST_F(ServerTest, ConnectionCloseAndHttp10CloseAfterTheAnswer) {
  RawClient closing(port());
  closing.send(get_request("/probe", "Connection: close\r\n"));
  auto response = closing.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->header("connection"), "close");
  EXPECT_TRUE(closing.wait_closed());

  RawClient old(port());
  old.send("GET /probe HTTP/1.0\r\n\r\n");
  response = old.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->version, "HTTP/1.0");
  EXPECT_TRUE(old.wait_closed());

  RawClient old_keep(port());
  old_keep.send("GET /probe HTTP/1.0\r\nConnection: keep-alive\r\n\r\n");
  response = old_keep.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->header("connection"), "keep-alive");
  old_keep.send("GET /probe HTTP/1.0\r\n\r\n");
  EXPECT_TRUE(old_keep.read_response());
}

TEST_F(ServerTest, ErrorsComeFromTheAgentWithTheirStatus) {
  const auto missing = get("/no/such/thing");
  EXPECT_EQ(missing.status, 404);
  const auto doc = parse_xml(missing.body);
  EXPECT_STREQ(doc.select_node("/MTConnectError/Errors/Error/@errorCode").attribute().value(),
               "INVALID_URI");
}

TEST_F(ServerTest, TheAgentGetsTheTargetSplitAndDecoded) {
  ASSERT_EQ(get("/mill/sample?from=3&path=a%20b+c").status, 404);  // the fake has no devices
  const Request seen = agent_->last_request();
  EXPECT_EQ(seen.method, "GET");
  ASSERT_TRUE(seen.target);
  EXPECT_EQ(seen.target->segments, (std::vector<std::string>{"mill", "sample"}));
  using Pairs = std::vector<std::pair<std::string, std::string>>;
  EXPECT_EQ(seen.target->query, (Pairs{{"from", "3"}, {"path", "a b c"}}));
  // A target that does not split reaches the agent as such: its answer.
  const auto bad = get("/current%zz");
  EXPECT_EQ(bad.status, 400);
  EXPECT_FALSE(agent_->last_request().target);
  EXPECT_STREQ(parse_xml(bad.body).select_node("//Error/@errorCode").attribute().value(),
               "INVALID_URI");
}

TEST_F(ServerTest, OtherMethodsGetTheAgentsUnsupportedAnswer) {
  RawClient client(port());
  client.send("DELETE /current HTTP/1.1\r\nHost: x\r\n\r\n");
  auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 405);
  EXPECT_NE(response->body.find("UNSUPPORTED"), std::string::npos);
  // Without a body the connection stays usable.
  client.send(get_request("/probe"));
  response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 200);
}

TEST_F(ServerTest, HeadAnswersTheHeadersOfGet) {
  agent_->add("door", "CLOSED");
  const auto full = get("/current");
  RawClient client(port());
  client.send("HEAD /current HTTP/1.1\r\nHost: x\r\n\r\n");
  const auto head = client.read_response(5s, true);
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_EQ(head->header("content-length"), std::to_string(full.body.size()));
  client.send(get_request("/probe"));  // no body was sent: next answer starts clean
  const auto next = client.read_response();
  ASSERT_TRUE(next);
  EXPECT_EQ(next->status, 200);
}

TEST_F(ServerTest, GarbageRequestLineGets400ErrorDocumentThenClose) {
  for (const std::string junk :
       {"HELLO\r\n\r\n", "GET\r\n\r\n", "GET / HTTP/9\r\n\r\n",
        "GET / HTTP/1.1\r\nBad Header\r\n\r\n", "G\x01T / HTTP/1.1\r\n\r\n"}) {
    RawClient client(port());
    client.send(junk);
    const auto response = client.read_response();
    ASSERT_TRUE(response) << junk;
    EXPECT_EQ(response->status, 400) << junk;
    const auto doc = parse_xml(response->body);
    EXPECT_STREQ(doc.select_node("//Error/@errorCode").attribute().value(), "INVALID_REQUEST");
    EXPECT_TRUE(client.wait_closed()) << junk;
  }
  EXPECT_EQ(get("/probe").status, 200);
}

TEST_F(ServerTest, BinaryJunkNeverHurtsOtherClients) {
  std::mt19937 random(42);
  RawClient bystander(port());
  for (int round = 0; round < 50; ++round) {
    std::string junk(1 + random() % 3000, '\0');
    for (auto& c : junk) {
      c = static_cast<char>(random());
    }
    RawClient client(port());
    client.try_send(junk);
    client.try_send("\r\n\r\n");
    // Either a 4xx answer or a closed connection, never a hang.
    const bool answered = client.read_until(
        [](const std::string& b) { return b.find("\r\n\r\n") != std::string::npos; }, 5s);
    if (answered) {
      EXPECT_EQ(client.buffer().compare(0, 10, "HTTP/1.1 4"), 0);
    }
    EXPECT_TRUE(client.wait_closed()) << "round " << round;
  }
  bystander.send(get_request("/probe"));
  const auto response = bystander.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 200);
}

TEST_F(ServerTest, UnsupportedHttpVersionGets505) {
  RawClient client(port());
  client.send("GET /probe HTTP/2.0\r\nHost: x\r\n\r\n");
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 505);
  EXPECT_TRUE(client.wait_closed());
}

TEST_F(ServerTest, ClientsThatResetMidAnswerDoNotHurtTheServer) {
  for (int i = 0; i < 2000; ++i) {
    agent_->add("item" + std::to_string(i % 500), std::to_string(i));
  }
  for (int round = 0; round < 50; ++round) {
    RawClient client(port());
    client.send(get_request("/sample?from=1") + get_request("/current"));
    client.reset();  // RST while the server is writing
  }
  RawClient streaming(port());
  streaming.send(get_request("/sample?interval=0&heartbeat=60000"));
  ASSERT_TRUE(streaming.read_stream_head());
  streaming.reset();
  EXPECT_EQ(get("/probe").status, 200);
  EXPECT_TRUE(eventually([&] { return server_->connection_count() == 0; }));
  EXPECT_TRUE(eventually([&] { return agent_->subscriber_count() == 0; }));
}

TEST_F(ServerTest, OversizedHeaderGets431AndClose) {
  RawClient client(port());
  client.try_send("GET /current HTTP/1.1\r\nX-Big: " + std::string(std::size_t{16} * 1024, 'a') +
                  "\r\n\r\n");
  const auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 431);
  EXPECT_TRUE(client.wait_closed());

  RawClient long_target(port());
  long_target.try_send(get_request("/" + std::string(20000, 'x')));
  const auto second = long_target.read_response();
  ASSERT_TRUE(second);
  EXPECT_EQ(second->status, 431);
  EXPECT_EQ(get("/probe").status, 200);
}

TEST_F(ServerTest, RequestBodiesAreRefused) {
  RawClient client(port());
  client.send("GET /current HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\n\r\nhello");
  auto response = client.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 413);
  EXPECT_TRUE(client.wait_closed());

  RawClient chunked(port());
  chunked.send(
      "POST /current HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n");
  response = chunked.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 405);  // the agent's UNSUPPORTED, then close
  EXPECT_TRUE(chunked.wait_closed());
}

TEST_F(ServerTest, StalledHeaderIsCutOffWhileOthersAreServed) {
  auto options = test_options();
  options.header_timeout = 300ms;
  restart(options);
  RawClient slow(port());
  slow.send("GET /current HTTP/1.1\r\nHost: x\r\n");  // never finishes
  RawClient silent(port());                           // never sends anything
  const auto started = std::chrono::steady_clock::now();
  EXPECT_EQ(get("/probe").status, 200);  // not held up by either
  EXPECT_TRUE(slow.wait_closed(5s));
  EXPECT_TRUE(silent.wait_closed(5s));
  EXPECT_GE(std::chrono::steady_clock::now() - started, 250ms);  // not closed early
  EXPECT_TRUE(eventually([&] { return server_->connection_count() == 0; }));
}

TEST_F(ServerTest, IdleKeepAliveConnectionIsClosed) {
  auto options = test_options();
  options.idle_timeout = 300ms;
  restart(options);
  RawClient client(port());
  client.send(get_request("/probe"));
  ASSERT_TRUE(client.read_response());
  EXPECT_TRUE(client.wait_closed(5s));
}

TEST_F(ServerTest, HalfOpenClientsGetTheirAnswerAndAreReleased) {
  RawClient asks_then_half_closes(port());
  asks_then_half_closes.send(get_request("/probe"));
  asks_then_half_closes.shutdown_write();
  const auto response = asks_then_half_closes.read_response();
  ASSERT_TRUE(response);
  EXPECT_EQ(response->status, 200);
  EXPECT_TRUE(asks_then_half_closes.wait_closed());

  RawClient half_closed(port());
  half_closed.shutdown_write();
  EXPECT_TRUE(half_closed.wait_closed());
  EXPECT_TRUE(eventually([&] { return server_->connection_count() == 0; }));
}

// At the limit, a new connection takes the place of the one that has
// waited longest without a request; only when every connection is busy
// (here: streaming) is it answered 503, and that passes when one ends.
TEST_F(ServerTest, ConnectionLimitMakesRoomFromWaitingConnectionsElse503) {
  auto options = test_options();
  options.max_connections = 4;
  restart(options);
  std::vector<std::unique_ptr<RawClient>> held;
  held.reserve(4);
  for (int i = 0; i < 4; ++i) {
    held.push_back(std::make_unique<RawClient>(port()));
    ASSERT_TRUE(eventually([&] { return server_->connection_count() == held.size(); }));
  }
  EXPECT_EQ(get("/probe").status, 200);
  EXPECT_TRUE(held.front()->wait_closed());  // the oldest idle one made room
  held.clear();
  ASSERT_TRUE(eventually([&] { return server_->connection_count() == 0; }));

  std::vector<std::unique_ptr<RawClient>> streams;
  for (int i = 0; i < 4; ++i) {
    streams.push_back(std::make_unique<RawClient>(port()));
    streams.back()->send(get_request("/sample?interval=0&heartbeat=60000"));
    ASSERT_TRUE(streams.back()->read_stream_head());
  }
  RawClient extra(port());
  const auto refused = extra.read_response();
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 503);
  EXPECT_TRUE(extra.wait_closed());

  streams.pop_back();
  ASSERT_TRUE(eventually([&] { return server_->connection_count() == 3; }));
  EXPECT_EQ(get("/probe").status, 200);
}

TEST_F(ServerTest, ManyConcurrentClientsAllGetAnswers) {
  agent_->add("door", "OPEN");
  std::vector<std::future<int>> clients;
  clients.reserve(32);
  for (int c = 0; c < 32; ++c) {
    clients.push_back(std::async(std::launch::async, [this] {
      RawClient client(port());
      int ok = 0;
      for (int i = 0; i < 25; ++i) {
        client.send(get_request("/current"));
        const auto response = client.read_response(10s);
        if (response && response->status == 200) {
          ++ok;
        }
      }
      return ok;
    }));
  }
  for (auto& client : clients) {
    EXPECT_EQ(client.get(), 25);
  }
}

TEST_F(ServerTest, StopClosesIdleConnectionsPromptly) {
  RawClient idle(port());
  idle.send(get_request("/probe"));
  ASSERT_TRUE(idle.read_response());
  const auto started = std::chrono::steady_clock::now();
  server_->stop();
  EXPECT_LT(std::chrono::steady_clock::now() - started, 3s);
  EXPECT_TRUE(idle.wait_closed(1s));
}

TEST(HttpServerBind, RefusesABadAddressAndABusyPort) {
  auto agent = std::make_shared<FakeAgent>();
  auto options = test_options();
  options.bind_address = "not-an-address";
  EXPECT_THROW(HttpServer(agent, options), std::system_error);
  HttpServer first(agent, test_options());
  options = test_options();
  options.port = first.port();
  EXPECT_THROW(HttpServer(agent, options), std::system_error);
}

}  // namespace
}  // namespace mtc::bridge::test
