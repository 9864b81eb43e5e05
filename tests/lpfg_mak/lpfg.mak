# lpfg runs this instead of its standard makefile: a helper unit, a define.
CXX_FLAGS=-O3 -std=gnu++11 -fPIC -DFACTOR=3
SRC_DIR=./include
OBJECTS=geo.o
%.o: $(SRC_DIR)/%.cpp
	g++ -I$(SRC_DIR) $(CXX_FLAGS) -c -o $@ $<
lsys.so: lsys.o $(OBJECTS)
	g++ $(CXX_FLAGS) -shared -o lsys.so lsys.o $(OBJECTS)
lsys.o: lsys.ii
	g++ -I$(SRC_DIR) $(CXX_FLAGS) -c lsys.ii
