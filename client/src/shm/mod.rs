pub struct ShmClient;
