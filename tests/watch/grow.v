projection: parallel
