//! Static obstacles and collision response through parry3d (the only module that imports it).
