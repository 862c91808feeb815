%% check slope_mfderi against central differences of the r.h.s. at a random point
setup_path();
[funcs,ip]=slope_funcs();
par=zeros(1,8); par([ip.k,ip.tau,ip.c,ip.a,ip.b,ip.cc,ip.d,ip.v])=[7,2,1e-3,3.2,7.2,4.8,1e-4,0.1];
rand('seed',1); randn('seed',1);
x=0.1*randn(5,2); u={randn(5,2),randn(5,2),randn(5,2)};
f=@(xx)funcs.sys_rhs(xx,par);
% deviations as nmfm_try_mfderi passes them: state and (zero) parameter rows, stacked
ext=cellfun(@(w)reshape([w;zeros(8,2)],[],1),u,'UniformOutput',false);
% D^j f[u1..uj] = d^j/dt1..dtj f(x+sum t_i u_i): mixed central differences
hs=[1e-5,1e-3,1e-2]; err=zeros(1,3); % truncation ~h^2 (order 1), rounding ~eps/h^j
for j=1:3
    h=hs(j);
    S=dec2bin(0:2^j-1)-'0'; acc=zeros(5,1);
    for r=1:size(S,1)
        sg=2*S(r,:)-1; dx=zeros(5,2);
        for i=1:j, dx=dx+sg(i)*h*u{i}; end
        acc=acc+prod(sg)*f(x+dx);
    end
    fd=acc/(2*h)^j; ex=slope_mfderi(x,par,ext{1:j});
    err(j)=norm(fd-ex)/norm(ex);
    fprintf('MFDERI order %d rel.err vs central differences %.2e\n',j,err(j));
end
% symmetric in its arguments and exact for complex deviations (bilinear, not sesquilinear)
uc={randn(5,2)+1i*randn(5,2),randn(5,2)+1i*randn(5,2)};
uc=cellfun(@(w)reshape([w;zeros(8,2)],[],1),uc,'UniformOutput',false);
e2=slope_mfderi(x,par,uc{:})-slope_mfderi(x,par,uc{[2 1]});
fprintf('MFDERI symmetry order 2 %.2e\n',norm(e2));
