// The tests' S3 server (tests/s3_server.hpp starts it): @20minutes/s3rver, installed globally
// by scripts/setup.sh, on 127.0.0.1 at an ephemeral port, storing its objects in the folder
// given, with the buckets given; it checks AWS Signature V4 (access key S3RVER, secret S3RVER)
// and writes its port to the file given once it listens.
// Usage: node --openssl-legacy-provider s3_server.js DATA_DIR PORT_FILE BUCKET...
// (its continuation tokens are DES-encrypted: OpenSSL 3 keeps DES in its legacy provider)
'use strict';

const { execSync } = require('child_process');
const fs = require('fs');
const path = require('path');

const [dataDir, portFile, ...buckets] = process.argv.slice(2);
const root = execSync('npm root -g').toString().trim();
const S3rver = require(path.join(root, '@20minutes', 's3rver'));

new S3rver({
  port: 0,
  address: '127.0.0.1',
  directory: dataDir,
  silent: true,
  vhostBuckets: false,
  configureBuckets: buckets.map((name) => ({ name })),
})
  .run()
  .then(({ port }) => {
    fs.writeFileSync(portFile + '.tmp', String(port));
    fs.renameSync(portFile + '.tmp', portFile);
  });
