// net/server_text: what a server sends is shown without the credentials in use (whole, or any
// piece of 12 characters of one, also when the server cut or encoded the rest), on one line,
// and cut to 200 characters naming its full length; the S3 configuration's credentials are the
// ones remembered.
#include <gtest/gtest.h>

#include "net/s3_config.hpp"
#include "net/server_text.hpp"

namespace lidarscout::net {
namespace {

const std::string kToken = "IQoJb3JpZ2luX2VjEHoaCXVzLWVhc3QtMSJHMEUCIQD+session/token=";

TEST(ServerText, RememberedCredentialsAreRedactedWholeAndInPieces) {
    remember_secret("AKIAREMEMBERED77");
    remember_secret(kToken);
    EXPECT_EQ(redact_secrets("key AKIAREMEMBERED77, token " + kToken + "."), "key [redacted], token [redacted].");
    EXPECT_EQ(redact_secrets("<Message>" + kToken.substr(5, 20) + "</Message>"), "<Message>[redacted]</Message>");
    // a token echoed percent-encoded: every stretch of 12 characters between the escapes is gone
    const std::string encoded = "IQoJb3JpZ2luX2VjEHoaCXVzLWVhc3QtMSJHMEUCIQD%2Bsession%2Ftoken%3D";
    const std::string shown = redact_secrets(encoded);
    EXPECT_EQ(shown.find("IQoJb3JpZ2lu"), std::string::npos) << shown;
    EXPECT_EQ(shown.rfind("[redacted]%2Bsession%2Ftoken%3D", 0), 0u) << shown;
    EXPECT_EQ(redact_secrets("nothing secret here"), "nothing secret here");
    remember_secret("abc");  // too short to be a secret: never looked for
    EXPECT_EQ(redact_secrets("abc"), "abc");
}

TEST(ServerText, TheS3ConfigurationsCredentialsAreRemembered) {
    S3Config c;
    c.access_key = "AKIACONFIGURED1";
    c.secret_key = "configured-secret-key-0f9e";
    c.session_token = "configured-session-token-5d4c";
    set_s3_config(c);
    set_s3_config(std::nullopt);
    const std::string shown =
        server_text("<Code>AKIACONFIGURED1</Code> configured-secret-key-0f9e configured-session-token-5d4c");
    EXPECT_EQ(shown, "<Code>[redacted]</Code> [redacted] [redacted]");
}

TEST(ServerText, OneLineCutNamingItsLength) {
    EXPECT_EQ(server_text("two\nlines"), "two\\x0Alines");
    const std::string cut = server_text(std::string(5000, 'x'));
    EXPECT_EQ(cut, std::string(200, 'x') + "... (5000 bytes)");
    const std::string accents = server_text(std::string(199, 'a') + "\xC3\xA9\xC3\xA9");  // never half a character
    EXPECT_EQ(accents, std::string(199, 'a') + "... (203 bytes)");
    EXPECT_EQ(server_text("short"), "short");
}

}  // namespace
}  // namespace lidarscout::net
