// The Redis client under the job store, against a real redis-server.

#include <gtest/gtest.h>

#include "redis.hpp"
#include "server/redis_process.hpp"

using namespace meshd::server::redis;
using meshd::test::RedisProcess;

TEST(RedisUrl, ParsesEveryFormAndKeepsThePasswordOutOfItsDescription) {
    Endpoint e = parse_url("redis://:s3cret@cache.example:6380/2");
    EXPECT_EQ(e.host, "cache.example");
    EXPECT_EQ(e.port, 6380);
    EXPECT_EQ(e.db, 2);
    EXPECT_EQ(e.password, "s3cret");
    EXPECT_EQ(e.describe().find("s3cret"), std::string::npos);
    e = parse_url("redis://localhost");
    EXPECT_EQ(e.port, 6379);
    EXPECT_EQ(e.db, 0);
    e = parse_url("unix:///run/redis.sock?db=3");
    EXPECT_EQ(e.socket, "/run/redis.sock");
    EXPECT_EQ(e.db, 3);
    for (const char* bad : {"http://x", "redis://", "redis://h:0", "redis://h:99999", "redis://h/x", "unix://relative"}) {
        try {
            parse_url(bad);
            ADD_FAILURE() << bad << " accepted";
        } catch (const std::invalid_argument& err) {
            EXPECT_EQ(std::string(err.what()).find("s3cret"), std::string::npos);
        }
    }
}

TEST(Redis, BinarySafeCommandsRepliesAndErrors) {
    RedisProcess server;
    Connection c(parse_url(server.url()), std::chrono::milliseconds(2000));
    EXPECT_TRUE(c.ping());
    const std::string bytes("a\0b\r\nc", 6);
    EXPECT_EQ(c.command({"SET", "k", bytes}).str, "OK");
    const Reply got = c.command({"GET", "k"});
    ASSERT_EQ(got.kind, Reply::Kind::String);
    EXPECT_EQ(got.str, bytes);
    EXPECT_TRUE(c.command({"GET", "missing"}).is_nil());
    EXPECT_EQ(c.command({"INCRBY", "n", "41"}).integer, 41);
    const Reply list = c.command(std::vector<std::string>{"MGET", "k", "missing", "n"});
    ASSERT_EQ(list.kind, Reply::Kind::Array);
    ASSERT_EQ(list.elements.size(), 3u);
    EXPECT_TRUE(list.elements[1].is_nil());
    EXPECT_EQ(list.elements[2].str, "41");
    // Redis's own errors are replies, not failures of the connection.
    const Reply wrong = c.command({"LPUSH", "k", "x"});
    EXPECT_TRUE(wrong.is_error());
    EXPECT_EQ(wrong.str.rfind("WRONGTYPE", 0), 0u);
    EXPECT_TRUE(c.connected());
    const auto replies = c.pipeline({{"INCR", "n"}, {"INCR", "n"}, {"GET", "n"}});
    ASSERT_EQ(replies.size(), 3u);
    EXPECT_EQ(replies[2].str, "43");
}

TEST(Redis, AFailedServerThrowsAndTheConnectionComesBackWithIt) {
    RedisProcess server(true);
    Connection c(parse_url(server.url()), std::chrono::milliseconds(500));
    EXPECT_EQ(c.command({"SET", "k", "v"}).str, "OK");
    server.stop();
    EXPECT_THROW(c.command({"GET", "k"}), Unavailable);
    EXPECT_FALSE(c.connected());
    EXPECT_FALSE(c.ping());
    server.start();
    EXPECT_TRUE(c.ping());  // reopened by itself (the data is gone: no persistence here)
    EXPECT_TRUE(c.command({"GET", "k"}).is_nil());
}

TEST(Redis, PasswordAndDatabaseAreSentOnEveryConnection) {
    RedisProcess server(false, {"--requirepass", "s3cret"});
    Endpoint e = parse_url(server.url());
    Connection anonymous(e, std::chrono::milliseconds(2000));
    EXPECT_TRUE(anonymous.command({"GET", "k"}).is_error());  // NOAUTH
    e.password = "wrong";
    Connection wrong(e, std::chrono::milliseconds(2000));
    try {
        wrong.command({"GET", "k"});
        ADD_FAILURE() << "a wrong password was accepted";
    } catch (const Unavailable& err) {
        EXPECT_EQ(std::string(err.what()).find("wrong"), std::string::npos) << "the password leaks: " << err.what();
    }
    e.password = "s3cret";
    e.db = 5;
    Connection c(e, std::chrono::milliseconds(2000));
    EXPECT_EQ(c.command({"SET", "k", "five"}).str, "OK");
    e.db = 0;
    Connection other(e, std::chrono::milliseconds(2000));
    EXPECT_TRUE(other.command({"GET", "k"}).is_nil());
}
