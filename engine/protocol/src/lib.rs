//! Wire protocol: length framing, a borrowing S-expression parser, typed percepts and actions for rcssservermj and SimSpark.
