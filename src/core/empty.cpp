// Keeps every area library non-empty while its sources are being written.
