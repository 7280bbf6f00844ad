// net/s3_config: credentials from the environment first, else from the profile of the shared
// credentials file (AWS_PROFILE, AWS_SHARED_CREDENTIALS_FILE) with its region from the config
// file; the region, endpoint, addressing style, anonymous and requester-pays variables; and
// clear errors for a missing profile, half a key pair or an unknown value.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/error.hpp"
#include "net/s3_config.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::net {
namespace {

// Sets the AWS variables of one test (every other one unset), restoring them afterwards.
class AwsEnvironment : public test::TempDirTest {
protected:
    static constexpr const char* kNames[] = {
        "AWS_ACCESS_KEY_ID", "AWS_SECRET_ACCESS_KEY", "AWS_SESSION_TOKEN", "AWS_PROFILE",
        "AWS_SHARED_CREDENTIALS_FILE", "AWS_CONFIG_FILE", "AWS_REGION", "AWS_DEFAULT_REGION", "AWS_ENDPOINT_URL",
        "AWS_ENDPOINT_URL_S3", "AWS_S3_ADDRESSING_STYLE", "AWS_NO_SIGN_REQUEST", "AWS_REQUEST_PAYER", "HOME"};

    void SetUp() override {
        TempDirTest::SetUp();
        for (const char* n : kNames) {
            if (const char* v = std::getenv(n)) saved_[n] = v;
            ::unsetenv(n);
        }
        ::setenv("HOME", dir.c_str(), 1);  // no ~/.aws of the user
    }
    void TearDown() override {
        for (const char* n : kNames) ::unsetenv(n);
        for (const auto& [n, v] : saved_) ::setenv(n.c_str(), v.c_str(), 1);
        TempDirTest::TearDown();
    }
    static void set(const char* name, const std::string& value) { ::setenv(name, value.c_str(), 1); }
    std::filesystem::path write(const std::string& name, const std::string& text) {
        const auto p = dir / name;
        std::ofstream(p) << text;
        return p;
    }

private:
    std::map<std::string, std::string> saved_;
};

TEST_F(AwsEnvironment, NothingSetIsAnonymousOnAws) {
    const S3Config c = s3_config_from_environment();
    EXPECT_TRUE(c.anonymous());
    EXPECT_EQ(c.region, "us-east-1");
    EXPECT_EQ(c.endpoint, "");
    EXPECT_FALSE(c.path_style("bucket"));
    EXPECT_TRUE(c.path_style("dotted.bucket"));  // (virtual hosts of dotted buckets fail TLS checks)
    EXPECT_FALSE(c.requester_pays);
}

TEST_F(AwsEnvironment, EnvironmentCredentialsComeFirst) {
    set("AWS_ACCESS_KEY_ID", "AKIAENV");
    set("AWS_SECRET_ACCESS_KEY", "envsecret");
    set("AWS_SESSION_TOKEN", "envtoken");
    set("AWS_SHARED_CREDENTIALS_FILE", write("creds", "[default]\naws_access_key_id = AKIAFILE\n"
                                                       "aws_secret_access_key = filesecret\n").string());
    set("AWS_REGION", "eu-west-3");
    set("AWS_DEFAULT_REGION", "us-west-2");
    const S3Config c = s3_config_from_environment();
    EXPECT_EQ(c.access_key, "AKIAENV");
    EXPECT_EQ(c.secret_key, "envsecret");
    EXPECT_EQ(c.session_token, "envtoken");
    EXPECT_EQ(c.region, "eu-west-3");
}

TEST_F(AwsEnvironment, ProfileOfTheCredentialsFileWithItsRegion) {
    set("AWS_SHARED_CREDENTIALS_FILE", write("creds", "[default]\naws_access_key_id=AKIADEF\n"
                                                       "aws_secret_access_key=def\n\n[survey]\n"
                                                       "aws_access_key_id = AKIASURVEY\n"
                                                       "aws_secret_access_key = s3cr3t\naws_session_token = tok\n")
                                              .string());
    set("AWS_CONFIG_FILE", write("config", "[default]\nregion = us-west-1\n[profile survey]\nregion = ca-central-1\n")
                               .string());
    S3Config c = s3_config_from_environment();
    EXPECT_EQ(c.access_key, "AKIADEF");
    EXPECT_EQ(c.region, "us-west-1");
    set("AWS_PROFILE", "survey");
    c = s3_config_from_environment();
    EXPECT_EQ(c.access_key, "AKIASURVEY");
    EXPECT_EQ(c.secret_key, "s3cr3t");
    EXPECT_EQ(c.session_token, "tok");
    EXPECT_EQ(c.region, "ca-central-1");
    set("AWS_DEFAULT_REGION", "ap-south-1");
    EXPECT_EQ(s3_config_from_environment().region, "ap-south-1");
}

TEST_F(AwsEnvironment, TheDefaultCredentialsFileIsInHome) {
    std::filesystem::create_directories(dir / ".aws");
    write(".aws/credentials", "[default]\naws_access_key_id=AKIAHOME\naws_secret_access_key=home\n");
    EXPECT_EQ(s3_config_from_environment().access_key, "AKIAHOME");
    set("AWS_NO_SIGN_REQUEST", "YES");
    EXPECT_TRUE(s3_config_from_environment().anonymous());
}

TEST_F(AwsEnvironment, MistakesAreErrorsThatNameThem) {
    const auto message = [] {
        try {
            s3_config_from_environment();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    set("AWS_PROFILE", "missing");
    set("AWS_SHARED_CREDENTIALS_FILE", write("creds", "[default]\naws_access_key_id=A\naws_secret_access_key=B\n")
                                              .string());
    EXPECT_NE(message().find("AWS_PROFILE \"missing\": no such profile"), std::string::npos) << message();
    ::unsetenv("AWS_PROFILE");
    set("AWS_ACCESS_KEY_ID", "AKIAONLY");
    EXPECT_NE(message().find("go together"), std::string::npos) << message();
    ::unsetenv("AWS_ACCESS_KEY_ID");
    set("AWS_S3_ADDRESSING_STYLE", "sideways");
    EXPECT_NE(message().find("AWS_S3_ADDRESSING_STYLE \"sideways\""), std::string::npos) << message();
    set("AWS_S3_ADDRESSING_STYLE", "virtual");
    set("AWS_REQUEST_PAYER", "bucket-owner");
    EXPECT_NE(message().find("AWS_REQUEST_PAYER"), std::string::npos) << message();
    ::unsetenv("AWS_REQUEST_PAYER");
    set("AWS_ENDPOINT_URL", "minio:9000");
    EXPECT_NE(message().find("not an http(s) URL"), std::string::npos) << message();
}

TEST_F(AwsEnvironment, EndpointAddressingAndRequesterPays) {
    set("AWS_ENDPOINT_URL", "http://127.0.0.1:9000/");
    set("AWS_REQUEST_PAYER", "requester");
    S3Config c = s3_config_from_environment();
    EXPECT_EQ(c.endpoint, "http://127.0.0.1:9000");
    EXPECT_TRUE(c.path_style("bucket"));  // another endpoint: path style by default
    EXPECT_TRUE(c.requester_pays);
    set("AWS_ENDPOINT_URL_S3", "https://s3.example.org");
    set("AWS_S3_ADDRESSING_STYLE", "virtual");
    c = s3_config_from_environment();
    EXPECT_EQ(c.endpoint, "https://s3.example.org");
    EXPECT_FALSE(c.path_style("bucket"));
}

}  // namespace
}  // namespace lidarscout::net
