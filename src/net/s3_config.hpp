// How s3:// URLs are reached: the credentials, region, endpoint, addressing style and
// requester-pays setting, read from the environment the way AWS tools read it:
//   AWS_ACCESS_KEY_ID, AWS_SECRET_ACCESS_KEY, AWS_SESSION_TOKEN  the credentials (first);
//   AWS_PROFILE (default "default") in AWS_SHARED_CREDENTIALS_FILE (default ~/.aws/credentials:
//     aws_access_key_id, aws_secret_access_key, aws_session_token), its region in
//     AWS_CONFIG_FILE (default ~/.aws/config);
//   AWS_REGION, else AWS_DEFAULT_REGION, else the profile's region, else us-east-1;
//   AWS_ENDPOINT_URL_S3, else AWS_ENDPOINT_URL: an S3-compatible store (MinIO, Ceph, Swift);
//   AWS_S3_ADDRESSING_STYLE: "virtual" (bucket.host/key) or "path" (host/bucket/key); by
//     default virtual on AWS and path on another endpoint (and for a bucket with a dot);
//   AWS_NO_SIGN_REQUEST=YES: anonymous requests even when credentials are found;
//   AWS_REQUEST_PAYER=requester (or --requester-pays): the requester pays the transfer.
// Without credentials the requests are anonymous (public buckets). The secret is only handed
// to libcurl, which signs each request (AWS Signature V4); it is never shown.
#pragma once

#include <optional>
#include <string>

namespace lidarscout::net {

struct S3Config {
    std::string access_key, secret_key, session_token;  // all empty: anonymous requests
    std::string region = "us-east-1";
    std::string endpoint;       // "" = AWS ("https://s3.REGION.amazonaws.com"); else "scheme://host:port"
    std::string addressing;     // "virtual", "path", or "" (the default of the endpoint)
    bool requester_pays = false;

    bool anonymous() const { return access_key.empty(); }
    bool path_style(const std::string& bucket) const;
};

// The configuration the environment gives (and the credentials and config files it names);
// throws Error for a profile that is named but missing, a file that cannot be read, half a
// key pair, or an unknown addressing style.
S3Config s3_config_from_environment();

// The process's configuration: read from the environment on first use, unless set.
S3Config s3_config();
void set_s3_config(std::optional<S3Config> config);  // nothing: read the environment again
// --requester-pays: on for every s3 request of the process.
void set_s3_requester_pays(bool on);

}  // namespace lidarscout::net
